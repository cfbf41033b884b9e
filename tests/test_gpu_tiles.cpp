// tiles against the CPU double-precision reference and against ppll: what only tiles promises (its
// two paths, its figures, lists of any length exact or refused, its loop budget). The scenes every
// exact method must match are in test_gpu_methods.cpp; the binning is tested on the CPU in
// test_tile_bins.cpp.
#include "gpu_test_env.h"
#include "render/methods/ppll.h"
#include "render/methods/tiles.h"
#include "sim/smoke_cloud_scene.h"
#include "test_scenes.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;
using testing::sphere;

class Tiles : public GpuTest {};

TEST_F(Tiles, SmokeCloudsMatchTheReference) {
    for (std::size_t n : {1000u, 20000u}) {
        const Scene s = make_smoke_cloud_scene(n, 96, 54);
        TilesMethod tiles(device());
        FrameStats stats;
        const Image img = tiles.render(s, &stats);
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << n << " spheres: " << describe(d);
        EXPECT_GT(stats.max_list_length, 40u) << "the cloud really is deep";
    }
}

TEST_F(Tiles, RandomOverlappingSpheresAndBoxesMatchTheReference) {
    Scene s = testing::random_scene(128, 96, 1000, 7, true);
    s.render.min_transmittance = 1e-4;  // early stops, as scene files do by default
    TilesMethod tiles(device());
    const Image img = tiles.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_TRUE(testing::all_finite(img));
}

// Without early stops both methods see every visible interval of every pixel: tiles' hits are
// ppll's list nodes, one for one.
TEST_F(Tiles, CountsTheSameIntervalsAsPpll) {
    const Scene s = make_smoke_cloud_scene(3000, 80, 60);
    TilesMethod tiles(device());
    PpllMethod ppll(device());
    FrameStats t, p;
    tiles.render(s, &t);
    ppll.render(s, &p, true);
    EXPECT_EQ(t.fragments, p.fragments);
    EXPECT_EQ(t.max_list_length, p.max_list_length);
    EXPECT_EQ(t.nonempty_pixels, p.nonempty_pixels);
    EXPECT_GT(t.fragments, 10000u);
    // Its memory is the tile lists, far less than a node per fragment.
    EXPECT_LT(t.pool_bytes, p.fragments * gpu::NODE_BYTES / 4);
}

// More media overlap than the open window holds (100 coincident spheres, 100 open at once): those
// pixels go to the general path, and stay exact.
TEST_F(Tiles, DeepOverlapTakesTheGeneralPathExactly) {
    const Scene s = testing::nearly_coincident_scene(48, 36);
    TilesMethod tiles(device());
    FrameStats stats;
    const Image img = tiles.render(s, &stats);
    EXPECT_EQ(stats.max_list_length, 100u);
    EXPECT_GT(stats.long_list_pixels, 0u);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

// The accurate shadow technique runs in this resolve too: the same image as ppll's, which
// test_gpu_light.cpp holds to the exact shadows of the reference.
TEST_F(Tiles, AccurateShadowsAsPpllHasThem) {
    Scene s = testing::random_scene(64, 48, 24, 11, false);
    s.lighting.shadows = true;
    s.lighting.sun_direction = {-0.7, -0.6, -0.3};
    Box ground{{-8, -1.5, -8}, {8, -1, 8}, {0.0, 0.0, 0.0}};
    ground.diffuse = {0.6, 0.6, 0.6};
    s.boxes = {ground};
    ASSERT_EQ(s.render.shadow_technique, ShadowTechnique::Accurate);
    TilesMethod tiles(device());
    PpllMethod ppll(device());
    const Image a = tiles.render(s), b = ppll.render(s);
    const ImageDiff d = compare_images(a, b, 1e-4);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    Scene plain = s;
    plain.lighting.shadows = false;
    EXPECT_GT(compare_images(a, tiles.render(plain), 1e-3).pixels_over, 100u) << "the shadows are missing";
}

// As for ppll (test_gpu_ppll.cpp): lists of 800, 3,000 and 20,000 nodes on one pixel's ray
// (testing::long_list_scene). A chain is always exact; coincident media go to the general path,
// exact where the loop budget allows, else the frame is refused.
using testing::LongList;

class TilesLongLists : public GpuTest, public ::testing::WithParamInterface<LongList> {};

TEST_P(TilesLongLists, AreExactOrRefusedNeverWrong) {
    const LongList p = GetParam();
    const Scene s = testing::long_list_scene(p);
    TilesMethod tiles(device());
    FrameStats stats;
    try {
        const Image img = tiles.render(s, &stats);
        if (!p.thick) {
            EXPECT_EQ(stats.max_list_length, std::uint32_t(p.nodes));
        }
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << describe(d);
        EXPECT_NE(img.pixel(7, 7)[0], img.pixel(0, 0)[0]) << "the list's medium is missing from the image";
    } catch (const ListResolveError& e) {
        // Only the general path runs out of budget, and only past 400 coincident media.
        EXPECT_TRUE(p.coincident && p.nodes > 400) << e.what();
        EXPECT_NE(std::string(e.what()).find("could not be resolved"), std::string::npos) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(Lengths, TilesLongLists,
                         ::testing::Values(LongList{800, false, false}, LongList{800, false, true},
                                           LongList{3000, false, false}, LongList{3000, false, true},
                                           LongList{20000, false, false}, LongList{20000, false, true},
                                           LongList{400, true, false}, LongList{400, true, true},
                                           LongList{800, true, false}, LongList{3000, true, true},
                                           LongList{20000, true, false}),
                         [](const ::testing::TestParamInfo<LongList>& info) { return testing::long_list_name(info.param); });

}  // namespace
}  // namespace brume
