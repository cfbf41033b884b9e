// `soft` (spherical billboards, Umenhoffer et al. 2006): exact where back-to-front "over" is exact,
// including spheres cut by geometry and by the eye, and measurably wrong where spheres intersect.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/soft.h"

#include <algorithm>
#include <stdexcept>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

// min_transmittance 0: back-to-front compositing integrates everything.
Scene small_scene(int w = 128, int h = 96) { return testing::small_scene(w, h); }

using testing::sphere;

class Soft : public GpuTest {};

TEST_F(Soft, SingleSphereMatchesReference) {
    Scene s = small_scene();
    testing::add_back_wall(s);
    s.spheres.push_back(sphere({0.3, -0.2, 0.0}, 1.1, 1.3));
    SoftMethod soft(device());
    const Image img = soft.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Soft, SpheresCutByGeometryAndByTheEyeAreClippedExactly) {
    // What `sorted` gets wrong: a sphere containing the eye with its centre behind it (its planar
    // billboard would be dropped), and spheres sliced by boxes (hard cuts at the billboard plane).
    // Their depth ranges are disjoint, so their order is exact too.
    Scene s = small_scene();
    s.boxes.push_back(Box{{-3, -3, -0.4}, {3, 0.3, 0.2}, {0.05, 0.1, 0.06}});  // a wall through sphere 1
    s.boxes.push_back(Box{{-9, -9, -9}, {9, -0.6, -2}, {0.3, 0.3, 0.3}});      // a floor under sphere 2
    s.spheres.push_back(sphere({0.0, 0.0, 5.3}, 1.0, 0.8, {0.8, 0.8, 0.9}));   // contains the eye
    s.spheres.push_back(sphere({0.2, 0.0, -0.3}, 1.0, 1.5));                   // centre inside the wall
    s.spheres.push_back(sphere({-0.5, -0.5, -3.5}, 0.9, 2.0, {0.3, 0.9, 0.4})); // half sunk in the floor
    SoftMethod soft(device());
    const Image img = soft.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Soft, NonIntersectingStackedSpheresMatchReference) {
    // Disjoint depth ranges, overlapping on screen, listed out of depth order.
    const Scene s = testing::stacked_scene();
    SoftMethod soft(device());
    const Image img = soft.render(s);
    EXPECT_EQ(soft.order(), (std::vector<std::uint32_t>{0, 3, 2, 4, 1}));
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Soft, StaysExactAcrossFramesAsOneSphereCirclesAnother) {
    // testing::circling_spheres: sphere 1 circles sphere 0, overlapping it on screen only where their
    // depth ranges are disjoint; sphere 3 joins for frames 2-4.
    SoftMethod soft(device());
    for (int frame = 0; frame < 7; ++frame) {
        Scene s = small_scene();
        s.boxes.push_back(Box{{-9, -9, -9}, {9, -0.3, -4}, {0.3, 0.3, 0.3}});  // cuts sphere 2
        s.spheres = testing::circling_spheres(frame);
        const Image img = soft.render(s);
        const std::vector<double> depth = view_depths(s);
        ASSERT_EQ(soft.order().size(), s.spheres.size());
        for (std::size_t i = 1; i < soft.order().size(); ++i)
            EXPECT_GE(depth[soft.order()[i - 1]], depth[soft.order()[i]]) << "frame " << frame;
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << "frame " << frame << ": " << describe(d);
    }
}

TEST_F(Soft, IntersectingSpheresDisagreeWithReference) {
    // Spheres that share volume: "over" of separately attenuated spheres is not the integral through
    // intersecting media (the limitation `ppll` removes).
    const Scene s = testing::intersecting_pair(0.35, 2.0, 0.0, 0.1);
    SoftMethod soft(device());
    const Image img = soft.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_GT(d.max_excess, 0.05) << describe(d);
    EXPECT_GT(d.pixels_over, 500u) << describe(d);
}

TEST_F(Soft, StillPopsWhenIntersectingParticlesSwapOrder) {
    SoftMethod soft(device());
    const testing::OrderFlip f = testing::flip_order(soft);
    EXPECT_GT(f.popping, 0.02);
    EXPECT_GT(f.popping, 30.0 * f.reference_step) << "popping " << f.popping << ", reference step " << f.reference_step;
}

TEST_F(Soft, FactoryTakesNoSetting) {
    // Called directly, not through the registry; the name: test_gpu_methods.cpp.
    EXPECT_THROW(make_soft_method(device(), "x"), std::invalid_argument);
}

}  // namespace
}  // namespace brume
