// SunLight's light-space grid is built on its first read (render/sun_light.h), which may come from
// several threads at once (the reference's workers): the grid and every depth read through it are
// the same as one thread's.
#include "render/sun_light.h"

#include "test_scenes.h"

#include <gtest/gtest.h>

#include <random>
#include <thread>
#include <vector>

namespace brume {
namespace {

TEST(SunLight, GridBuiltOnFirstReadFromManyThreadsIsOneThreadsGrid) {
    const Scene s = testing::random_sun_cloud(400, 5u, {0.3, -1.0, 0.2}, 0.05, 0.9, {0.0, 0.0, 0.0}, 17);
    std::vector<glm::dvec3> points;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(-3.0, 3.0);
    for (int n = 0; n < 2000; ++n) points.emplace_back(pos(rng), pos(rng) * 0.7 + 0.5, pos(rng));

    const SunLight alone(s);
    std::vector<double> want;
    for (const glm::dvec3& x : points) want.push_back(alone.optical_depth(x));

    for (int attempt = 0; attempt < 8; ++attempt) {
        const SunLight shared(s);  // no grid yet: the threads below race to its first read
        constexpr int kThreads = 4;
        std::vector<std::vector<double>> got(kThreads);
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t)
            threads.emplace_back([&, t] {
                for (const glm::dvec3& x : points) got[std::size_t(t)].push_back(shared.optical_depth(x));
            });
        for (std::thread& t : threads) t.join();
        for (int t = 0; t < kThreads; ++t) ASSERT_EQ(got[std::size_t(t)], want) << "thread " << t;
        EXPECT_EQ(shared.grid_side(), alone.grid_side());
        EXPECT_EQ(shared.cell_start(), alone.cell_start());
        EXPECT_EQ(shared.cell_items(), alone.cell_items());
    }
    int shadowed = 0;
    for (double d : want) shadowed += d > 0.0;
    EXPECT_GT(shadowed, 500);  // the points saw depths, not only zeros
    EXPECT_GT(alone.grid_side(), 1);
}

// Without shadows there is no grid, and reading it builds nothing.
TEST(SunLight, NoShadowsNoGrid) {
    Scene s = testing::random_sun_cloud(50, 3u, {0.0, -1.0, 0.0}, 0.05, 0.9, {0.0, 0.0, 0.0}, 17);
    s.lighting.shadows = false;
    const SunLight sun(s);
    EXPECT_EQ(sun.grid_side(), 0);
    EXPECT_TRUE(sun.cell_items().empty());
    EXPECT_EQ(sun.optical_depth(glm::dvec3(0.0)), 0.0);
    EXPECT_EQ(sun.transmittance(glm::dvec3(0.0)), 1.0);
}

}  // namespace
}  // namespace brume
