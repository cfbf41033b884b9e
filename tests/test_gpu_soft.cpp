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

Scene small_scene(int w = 128, int h = 96) {
    Scene s;
    s.source = "test";
    s.camera.position = {0.0, 0.0, 5.0};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.width = w;
    s.camera.height = h;
    s.render.min_transmittance = 0.0;  // back-to-front compositing integrates everything
    return s;
}

using testing::sphere;

class Soft : public GpuTest {};

TEST_F(Soft, SingleSphereMatchesReference) {
    Scene s = small_scene();
    s.boxes.push_back(Box{{-20, -20, -12}, {20, 20, -10}, {0.3, 0.25, 0.2}});
    s.spheres.push_back(sphere({0.3, -0.2, 0.0}, 1.1, 1.3));
    SoftMethod soft(device());
    FrameStats stats;
    const Image img = soft.render(s, &stats);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_GT(stats.total_ms, 0.0);
    EXPECT_GT(stats.memory_bytes, 0u);
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
    Scene s = small_scene();
    s.boxes.push_back(Box{{-20, -20, -12}, {20, 20, -10}, {0.3, 0.25, 0.2}});
    s.spheres.push_back(sphere({0.2, 0.1, -3.2}, 1.2, 0.6, {0.9, 0.3, 0.2}));   // z in [-4.4, -2.0]
    s.spheres.push_back(sphere({-0.3, -0.1, 2.6}, 0.5, 2.5, {0.2, 0.8, 0.3}));  // [2.1, 3.1]
    s.spheres.push_back(sphere({0.0, 0.2, 0.3}, 0.9, 1.0, {0.3, 0.4, 0.95}));   // [-0.6, 1.2]
    s.spheres.push_back(sphere({0.5, -0.3, -1.3}, 0.6, 4.0, {0.95, 0.9, 0.3})); // [-1.9, -0.7]
    s.spheres.push_back(sphere({-0.4, 0.3, 1.6}, 0.3, 0.8, {0.8, 0.8, 0.8}));   // [1.3, 1.9]
    SoftMethod soft(device());
    const Image img = soft.render(s);
    EXPECT_EQ(soft.order(), (std::vector<std::uint32_t>{0, 3, 2, 4, 1}));
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Soft, StaysExactAcrossFramesAsOneSphereCirclesAnother) {
    // Sphere 1 circles sphere 0 (in front, past it at the side, behind, back), overlapping it on
    // screen only where their depth ranges are disjoint; sphere 3 joins for frames 2-4.
    const glm::dvec3 path[7] = {{0, 0, 2}, {1.5, 0, 1}, {1.5, 0, -1}, {0, 0.05, -2}, {-1.5, 0, -1}, {-1.5, 0, 1}, {0, 0, 2}};
    SoftMethod soft(device());
    for (int frame = 0; frame < 7; ++frame) {
        Scene s = small_scene();
        s.boxes.push_back(Box{{-9, -9, -9}, {9, -0.3, -4}, {0.3, 0.3, 0.3}});  // cuts sphere 2
        s.spheres.push_back(sphere({0, 0, 0}, 0.5, 2.0, {0.9, 0.2, 0.2}));
        s.spheres.push_back(sphere(path[frame], 0.4, 3.0, {0.2, 0.9, 0.3}));
        s.spheres.push_back(sphere({0, 0, -5}, 1.5, 0.7, {0.3, 0.3, 0.9}));
        if (frame >= 2 && frame < 5) s.spheres.push_back(sphere({0.1, -0.1, 3.0}, 0.2, 5.0, {0.9, 0.9, 0.9}));
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
    Scene s = small_scene();
    s.spheres.push_back(sphere({-0.35, 0.0, 0.0}, 1.0, 2.0, {0.95, 0.2, 0.1}));
    s.spheres.push_back(sphere({0.35, 0.0, 0.1}, 1.0, 2.0, {0.1, 0.3, 0.95}));
    SoftMethod soft(device());
    const Image img = soft.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_GT(d.max_excess, 0.05) << describe(d);
    EXPECT_GT(d.pixels_over, 500u) << describe(d);
}

TEST_F(Soft, StillPopsWhenIntersectingParticlesSwapOrder) {
    Scene a = small_scene();
    a.spheres.push_back(sphere({-0.3, 0.0, 0.001}, 1.0, 2.5, {0.95, 0.2, 0.1}));
    a.spheres.push_back(sphere({0.3, 0.0, 0.0}, 1.0, 2.5, {0.1, 0.3, 0.95}));
    Scene b = a;
    b.spheres[0].center.z = -0.001;
    SoftMethod soft(device());
    const Image ia = soft.render(a);
    const Image ib = soft.render(b);
    const Image ra = render_reference(a), rb = render_reference(b);
    const double popping = temporal_error(ib, ia, rb, ra);
    const double reference_step = temporal_error(rb, ra, ra, ra);
    EXPECT_GT(popping, 0.02);
    EXPECT_GT(popping, 30.0 * reference_step) << "popping " << popping << ", reference step " << reference_step;
}

TEST_F(Soft, FactoryTakesNoSetting) {
    EXPECT_EQ(make_soft_method(device(), "")->name(), "soft");
    EXPECT_THROW(make_soft_method(device(), "x"), std::invalid_argument);
}

}  // namespace
}  // namespace brume
