// The preview's heat map of list length (render/frame/list_heat_map.h): its per-pixel counts are the
// depth complexity of the closed-form layers scene, the CPU's count (reference_list_lengths) on a
// random scene with boxes, and exactly the lengths ppll's lists have (ppll's own list statistics).
#include "gpu_test_env.h"
#include "test_scenes.h"

#include "render/frame/frame_path.h"
#include "render/frame/list_heat_map.h"
#include "render/methods/ppll.h"
#include "render/reference.h"
#include "sim/layers_scene.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace brume {
namespace {

using testing::GpuTest;

class ListHeatMapTest : public GpuTest {};

// Every pixel of the layers scene meets layers / 2 spheres, each entered and left ahead of the eye.
TEST_F(ListHeatMapTest, LayersSceneCountsHalfTheLayersEverywhere) {
    for (int layers : {2, 8, 16}) {
        const Scene s = make_layers_scene(layers, 64, 48);
        ListHeatMap heat(device());
        const Image counts = heat.render(s);
        int wrong = 0;
        for (std::uint32_t n : list_lengths(counts)) wrong += n != std::uint32_t(layers / 2);
        EXPECT_EQ(wrong, 0) << layers << " layers";
        const ListLengthFigures f = list_length_figures(counts);
        EXPECT_EQ(f.total, std::uint64_t(64 * 48 * layers / 2));
        EXPECT_EQ(f.nonempty_pixels, std::uint64_t(64 * 48));
        EXPECT_DOUBLE_EQ(f.longest, layers / 2.0);
    }
}

// A sphere behind an opaque wall has an empty interval: the wall's distance clips it, as in ppll.
TEST_F(ListHeatMapTest, OpaqueSurfacesClipTheCount) {
    Scene s = testing::small_scene(32, 24);
    s.spheres.push_back(testing::sphere({0.0, 0.0, 0.0}, 1.0, 1.0));
    ListHeatMap heat(device());
    const ListLengthFigures open = list_length_figures(heat.render(s));
    EXPECT_GT(open.nonempty_pixels, 0u);
    EXPECT_DOUBLE_EQ(open.longest, 1.0);
    s.boxes.push_back(Box{{-20, -20, 2.0}, {20, 20, 2.5}, {0.3, 0.3, 0.3}});  // between the eye and the sphere
    const ListLengthFigures hidden = list_length_figures(heat.render(s));
    EXPECT_EQ(hidden.nonempty_pixels, 0u);
    EXPECT_EQ(hidden.total, 0u);
}

// Against the CPU's count, pixel by pixel: rays grazing a silhouette may round either way in float
// (a few in a thousand, off by one), nothing else may differ. And against ppll through one shared
// frame path, as the preview runs them: the same total, longest list and non-empty pixels, exactly.
TEST_F(ListHeatMapTest, MatchesTheCpuCountAndPpllsLists) {
    Scene s = testing::random_scene(128, 96, 400, 17, true);
    s.render.min_transmittance = 1e-4;
    FramePath path(device());
    PpllMethod ppll(device());
    FrameStats stats;
    path.render(ppll, s, &stats, true);
    ASSERT_TRUE(stats.list_stats);
    ListHeatMap heat(device());
    const Image counts = path.render(heat, s);
    const std::vector<std::uint32_t> gpu = list_lengths(counts);
    const std::vector<std::uint32_t> cpu = reference_list_lengths(s);
    ASSERT_EQ(gpu.size(), cpu.size());
    std::size_t differing = 0, far_off = 0;
    for (std::size_t p = 0; p < gpu.size(); ++p) {
        differing += gpu[p] != cpu[p];
        far_off += std::abs(int(gpu[p]) - int(cpu[p])) > 1;
    }
    EXPECT_LE(differing, gpu.size() * 3 / 1000);
    EXPECT_EQ(far_off, 0u);
    const ListLengthFigures f = list_length_figures(counts);
    EXPECT_GT(f.total, 10000u);  // the scene is deep enough to mean something
    EXPECT_EQ(f.total, stats.fragments);
    EXPECT_EQ(f.nonempty_pixels, stats.nonempty_pixels);
    EXPECT_DOUBLE_EQ(f.longest, double(stats.max_list_length));
    // The heat map's own path gives the same counts as the shared one.
    EXPECT_TRUE(testing::same_bits(counts, ListHeatMap(device()).render(s)));
}

}  // namespace
}  // namespace brume
