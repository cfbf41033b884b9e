// SunLight's light-space grid is built on its first read (render/sun_light.h), which may come from
// several threads at once (the reference's workers): the grid and every depth read through it are
// the same as one thread's.
#include "render/sun_light.h"

#include "test_scenes.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
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

// An atmosphere around a cloud (render/outsized_spheres.h): the sphere 10,000 times a puff's radius is
// listed in no cell, the grid's cells follow the puffs (about a puff across, where the atmosphere's extent
// and radius made them 670 units wide and every lookup walked every puff), and every lookup still takes
// its chord: the depths are the sum over all spheres of each chord's closed form.
TEST(SunLight, AnOutsizedSphereIsInNoCellAndEveryLookupTakesIt) {
    Scene s = testing::random_sun_cloud(200, 9u, {0.3, -1.0, 0.2}, 0.3, 0.7);
    s.spheres.push_back(testing::sphere({40.0, -30.0, 20.0}, 1e4, 1e-4));
    const std::uint32_t atmosphere = std::uint32_t(s.spheres.size() - 1);
    const SunLight sun(s);
    EXPECT_EQ(sun.outsized_indices(), std::vector<std::uint32_t>{atmosphere});
    EXPECT_EQ(std::count(sun.cell_items().begin(), sun.cell_items().end(), atmosphere), 0);
    EXPECT_LT(sun.grid_cell(), 2.0);
    std::size_t longest = 0;
    for (std::size_t c = 0; c + 1 < sun.cell_start().size(); ++c)
        longest = std::max<std::size_t>(longest, sun.cell_start()[c + 1] - sun.cell_start()[c]);
    EXPECT_LT(longest, 60u);  // of 200 puffs

    const glm::dvec3 l = sun.toward_sun();
    // sum over spheres [first, last) of tau times the chord above x, in closed form.
    const auto closed_form = [&](const glm::dvec3& x, std::size_t first, std::size_t last) {
        double depth = 0.0;
        for (std::size_t k = first; k < last; ++k) {
            const Sphere& sp = s.spheres[k];
            const glm::dvec3 oc = x - sp.center;
            const double b = glm::dot(oc, l), perp2 = glm::dot(oc, oc) - b * b, disc = sp.radius * sp.radius - perp2;
            if (!(disc > 0.0)) continue;
            const double half = std::sqrt(disc);
            depth += sp.extinction * (-b - half >= 0.0 ? 2.0 * half : std::max(half - b, 0.0));
        }
        return depth;
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> near(-3.0, 3.0), far(-5000.0, 5000.0);
    int in_puffs_shadow = 0;
    for (int n = 0; n < 3000; ++n) {
        // Under and in the cloud, and far beside it (outside the grid, inside the atmosphere).
        const glm::dvec3 x = n % 3 == 2 ? glm::dvec3(far(rng), far(rng) * 0.5, far(rng))
                                        : glm::dvec3(near(rng), near(rng) * 0.7 + 0.5, near(rng));
        const double want = closed_form(x, 0, s.spheres.size()), got = sun.optical_depth(x);
        ASSERT_NEAR(got, want, 1e-9 * std::max(1.0, want)) << "point " << n;
        ASSERT_GT(got, 0.0) << "point " << n;  // inside the atmosphere, below its top
        in_puffs_shadow += closed_form(x, 0, atmosphere) > 0.01;
    }
    EXPECT_GT(in_puffs_shadow, 200);  // the points saw the puffs' shadows, not the atmosphere alone
}

// Between two neighbouring kinks of a ray the reference reads T_sun through a ShadowSet taken once, in
// the middle (render/reference.cpp sun_integral): at every point of that stretch it must give T_sun as
// the full lookup does, with spheres entering and leaving the set from stretch to stretch, boxes' shadows,
// an outsized sphere, rays that start inside the smoke, and rays along the sun (no distance across it).
TEST(SunLight, AShadowSetTakenBetweenTwoKinksHoldsAtEveryPointBetweenThem) {
    Scene s = testing::random_sun_cloud(300, 4u, {0.3, -1.0, 0.2}, 0.1, 0.6);
    s.spheres.push_back(testing::sphere({0.5, 1.0, -0.3}, 60.0, 0.01));  // an atmosphere (outsized)
    s.boxes.push_back(Box{{-3, -2, -3}, {3, -1.5, 3}, {}, {0.5, 0.5, 0.5}});
    s.boxes.push_back(Box{{0.2, -1.5, 0.1}, {0.5, 3.5, 0.4}, {}, {0.5, 0.5, 0.5}});
    const SunLight sun(s);
    ASSERT_EQ(sun.outsized_indices().size(), 1u);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> pos(-3.0, 3.0), unit(-1.0, 1.0), frac(0.0, 1.0);
    SunLight::ShadowSet set;
    std::vector<double> kinks;
    std::size_t stretches = 0, blocked = 0, largest = 0, changed = 0;
    for (int r = 0; r < 300; ++r) {
        const glm::dvec3 o(pos(rng), pos(rng) * 0.6 + 1.0, pos(rng));
        glm::dvec3 d(unit(rng), unit(rng), unit(rng));
        if (r % 10 == 0) d = r % 20 == 0 ? sun.toward_sun() : -sun.toward_sun();
        d = glm::normalize(d);
        kinks.clear();
        sun.kinks(o, d, 0.0, 8.0, kinks);
        kinks.push_back(0.0);
        kinks.push_back(8.0);
        std::sort(kinks.begin(), kinks.end());
        std::size_t previous_members = 0;
        for (std::size_t k = 0; k + 1 < kinks.size(); ++k) {
            const double p = kinks[k], q = kinks[k + 1];
            if (!(q > p)) continue;
            sun.shadow_set(o, d, 0.5 * (p + q), set);
            ++stretches;
            blocked += set.box_blocked;
            const std::size_t members = std::size_t(std::count_if(set.weight.begin(), set.weight.end(),
                                                                  [](double w) { return w > 0.0; }));
            largest = std::max(largest, members);
            changed += members != previous_members;
            previous_members = members;
            for (const double f : {1e-6, 0.01, frac(rng), 0.5, frac(rng), 0.99, 1.0 - 1e-6}) {
                const double t = p + f * (q - p);
                const double want = sun.transmittance(o + t * d);
                const double got = set.box_blocked ? 0.0 : std::exp(-SunLight::optical_depth(set, t));
                ASSERT_NEAR(got, want, (f < 0.001 || f > 0.999) ? 1e-9 : 1e-12) << "ray " << r << " stretch " << k << " at " << f;
            }
        }
    }
    // The rays crossed many shadows: sets of many sizes, some under a box.
    EXPECT_GT(stretches, 5000u);
    EXPECT_GT(blocked, 50u);
    EXPECT_GT(largest, 10u);
    EXPECT_GT(changed, 2000u);
}

}  // namespace
}  // namespace brume
