// ppll against closed forms and the CPU double-precision reference: what only ppll promises (list
// statistics, the pool's growth, budget and parts, lists of any length, order independence). The
// scenes every exact method must match (one sphere, the eye inside media and crossing the eye plane,
// spheres cut by boxes, tangent and coincident spheres, no medium at all) are in test_gpu_methods.cpp.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/ppll.h"
#include "sim/layers_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::all_finite;
using testing::compare_with_reference;
using testing::GpuTest;

Scene small_scene(int w = 128, int h = 96) { return testing::small_scene(w, h); }

using testing::sphere;

class Ppll : public GpuTest {};

TEST_F(Ppll, TwoOverlappingSpheresMatchReference) {
    Scene s = small_scene();
    s.spheres.push_back(sphere({-0.4, 0.1, 0}, 1.0, 1.5, {0.9, 0.2, 0.2}));
    s.spheres.push_back(sphere({0.5, -0.1, 0.3}, 0.9, 3.0, {0.2, 0.3, 0.95}));
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_EQ(stats.max_list_length, 2u);
}

// testing::random_scene at 128 x 96, stopping at transmittance 1e-4 as scene files do by default.
Scene random_scene(int count, unsigned seed, bool with_boxes) {
    Scene s = testing::random_scene(128, 96, count, seed, with_boxes);
    s.render.min_transmittance = 1e-4;
    return s;
}

TEST_F(Ppll, ThousandRandomOverlappingSpheresMatchReference) {
    const Scene s = random_scene(1000, 7, true);
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_GT(stats.max_list_length, 20u);  // the scene really is deep
    EXPECT_TRUE(all_finite(img));
}

TEST_F(Ppll, ExtinctionFromOneMillionthToTenThousand) {
    for (double tau : {1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4}) {
        Scene s = small_scene(64, 48);
        s.lighting.background = {0, 0, 0};
        s.spheres.push_back(sphere({-0.3, 0, 0}, 1.0, tau));
        s.spheres.push_back(sphere({0.4, 0.1, 0.2}, 0.7, tau * 3.0, {0.3, 0.5, 0.7}));
        PpllMethod ppll(device());
        const Image img = ppll.render(s);
        ASSERT_TRUE(all_finite(img)) << "tau " << tau;
        // Relative to the image's own peak, so 1e-6 media are checked as strictly as opaque ones:
        // a cancelling 1 - exp(-x) would be off by ~1e-2 relative at tau = 1e-6.
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << "tau " << tau << ": " << describe(d);
        EXPECT_GT(d.peak, 0.0);
    }
}

TEST_F(Ppll, ShuffledParticleOrderGivesTheSameImage) {
    Scene s = random_scene(300, 11, false);
    PpllMethod ppll(device());
    const Image a = ppll.render(s);
    std::mt19937 rng(3);
    std::shuffle(s.spheres.begin(), s.spheres.end(), rng);
    const Image b = ppll.render(s);
    // Only events at exactly equal distances may be summed in another order.
    const ImageDiff d = compare_images(b, a, 1e-6);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Ppll, TinyPoolRegrowsAndStaysExact) {
    const Scene s = random_scene(200, 5, true);
    PpllOptions options;
    options.initial_nodes = 16;  // far too small: the first frame must overflow
    PpllMethod ppll(device(), options);
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    EXPECT_GE(stats.regrows, 1);
    EXPECT_GE(stats.pool_capacity, stats.fragments);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    // The grown pool serves the next frame without regrowing.
    ppll.render(s, &stats);
    EXPECT_EQ(stats.regrows, 0);
}

TEST_F(Ppll, BudgetTooSmallStatesTheBytesNeeded) {
    const Scene s = random_scene(200, 5, false);
    PpllOptions options;
    options.max_pool_bytes = 64 * 1024;  // 4096 nodes, far fewer than the scene needs
    options.initial_nodes = 16;
    PpllMethod ppll(device(), options);
    FrameStats stats;
    try {
        ppll.render(s, &stats);
        FAIL() << "expected PoolBudgetError";
    } catch (const PoolBudgetError& e) {
        EXPECT_GT(e.bytes_needed(), e.bytes_allowed());
        EXPECT_EQ(e.bytes_allowed(), 64u * 1024u);
        EXPECT_EQ(e.bytes_needed() % 16, 0u);
        EXPECT_NE(std::string(e.what()).find("bytes"), std::string::npos) << e.what();
    }
    // An unconstrained renderer measures the same need exactly.
    PpllMethod unconstrained(device());
    unconstrained.render(s, &stats);
    PpllMethod again(device(), options);
    try {
        again.render(s);
    } catch (const PoolBudgetError& e) {
        EXPECT_EQ(e.bytes_needed(), stats.fragments * 16);
    }
}

TEST_F(Ppll, PoolSplitIntoPartsStaysExact) {
    // Parts of 8,192 nodes stand in for the 128 MiB storage-buffer limit: a scene needing several
    // parts must resolve exactly, lists linking nodes in different parts included.
    const Scene s = random_scene(300, 13, true);
    PpllOptions options;
    options.part_nodes = 8192;
    options.initial_nodes = 16;  // and grow across part counts on the way
    PpllMethod ppll(device(), options);
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    ASSERT_GT(stats.fragments, 3u * 8192u) << "the scene must need several parts";
    EXPECT_GE(stats.regrows, 1);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Ppll, MorePartsThanAddressableIsABudgetError) {
    // Eight parts of 1,024 nodes address 8,192 nodes: a scene needing more must say so.
    const Scene s = random_scene(300, 13, true);
    PpllOptions options;
    options.part_nodes = 1024;
    PpllMethod ppll(device(), options);
    EXPECT_EQ(ppll.max_pool_nodes(), 8u * 1024u);
    try {
        ppll.render(s);
        FAIL() << "expected PoolBudgetError";
    } catch (const PoolBudgetError& e) {
        EXPECT_NE(std::string(e.what()).find("can address"), std::string::npos) << e.what();
    }
}

TEST_F(Ppll, NearlySortedListsLongerThanTheWindowTakeTheOrderedPath) {
    // 60 spheres on the view axis: 60 nodes = 120 events per pixel, far more than the ordered
    // window's 32 slots, with many ties in distance between neighbouring spheres' surfaces. Drawn
    // far to near, every list arrives sorted by the spheres' bounds and needs no second walk.
    Scene s = small_scene(48, 48);
    s.render.min_transmittance = 0.0;
    for (int i = 0; i < 60; ++i) s.spheres.push_back(sphere({0.01 * i, 0.0, 2.0 - 0.07 * i}, 1.0, 0.05));
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    EXPECT_EQ(stats.max_list_length, 60u);
    EXPECT_EQ(stats.long_list_pixels, 0u);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Ppll, MoreOverlappingMediaThanTheWindowHoldsTakeTheGeneralPathExactly) {
    // 100 nearly coincident spheres: every one is open at once, so the window cannot hold the
    // pending exits; those pixels are resolved again by the general path, and stay exact.
    const Scene s = testing::nearly_coincident_scene(48, 48);
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    EXPECT_EQ(stats.max_list_length, 100u);
    EXPECT_GT(stats.long_list_pixels, 0u);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

// Lists of 800, 3,000 and 20,000 nodes, thin (no early stop) and thick (early stop), on one pixel
// (15 x 15: the centre pixel's ray is the view axis). A chain of disjoint spheres along the axis
// is nearly sorted and must always be exact. Coincident spheres keep every medium open at once;
// the general path resolves them exactly where the device lets its loops run long enough
// (lavapipe: 400 nodes, not 800), and otherwise the frame is refused: never a wrong image.
using testing::LongList;

class PpllLongLists : public GpuTest, public ::testing::WithParamInterface<LongList> {};

TEST_P(PpllLongLists, AreExactOrRefusedNeverWrong) {
    const LongList p = GetParam();
    const Scene s = testing::long_list_scene(p);
    PpllMethod ppll(device());
    FrameStats stats;
    try {
        const Image img = ppll.render(s, &stats, true);
        EXPECT_EQ(stats.max_list_length, std::uint32_t(p.nodes));
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << describe(d);
        const float* centre = img.pixel(7, 7);
        const float* corner = img.pixel(0, 0);
        EXPECT_NE(centre[0], corner[0]) << "the list's medium is missing from the image";
    } catch (const ListResolveError& e) {
        // Only the general path may run out of loop iterations, and only past 400 nodes.
        EXPECT_TRUE(p.coincident && p.nodes > 400) << e.what();
        EXPECT_NE(std::string(e.what()).find("could not be resolved"), std::string::npos) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(Lengths, PpllLongLists,
                         ::testing::ValuesIn(testing::long_lists(true)),
                         [](const ::testing::TestParamInfo<LongList>& info) { return testing::long_list_name(info.param); });

TEST_F(Ppll, LayersSceneHasExactlyTheStatedLayersEverywhere) {
    for (int layers : {2, 8}) {
        const Scene s = make_layers_scene(layers, 64, 48);
        PpllMethod ppll(device());
        FrameStats stats;
        const Image img = ppll.render(s, &stats);
        EXPECT_EQ(stats.fragments, std::uint64_t(64 * 48 * layers / 2));
        EXPECT_EQ(stats.max_list_length, std::uint32_t(layers / 2));
        EXPECT_EQ(stats.nonempty_pixels, std::uint64_t(64 * 48));
        EXPECT_DOUBLE_EQ(stats.mean_list_length, layers / 2.0);
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    }
}

TEST_F(Ppll, ListStatisticsMatchTheCpuDepthComplexity) {
    const Scene s = random_scene(400, 17, true);
    PpllMethod ppll(device());
    FrameStats stats;
    ppll.render(s, &stats);
    const std::vector<std::uint32_t> lengths = reference_list_lengths(s);
    std::uint64_t total = 0, nonempty = 0;
    std::uint32_t longest = 0;
    for (std::uint32_t n : lengths) {
        total += n;
        nonempty += n > 0;
        longest = std::max(longest, n);
    }
    // Rays grazing a silhouette may round either way in float: allow a few in a thousand.
    EXPECT_NEAR(double(stats.fragments), double(total), 3e-3 * double(total));
    EXPECT_NEAR(double(stats.nonempty_pixels), double(nonempty), 3e-3 * double(nonempty));
    EXPECT_NEAR(double(stats.max_list_length), double(longest), 1.0);
}

}  // namespace
}  // namespace brume
