// wsum, wavg and wboit (Maule, "Survey on Order Independent Transparency Techniques", section 5;
// McGuire & Bavoil 2013): exact where a pixel sees one
// sphere, independent of draw order, and wrong in the documented way when a dark dense sphere hides
// a bright one.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/ppll.h"
#include "render/methods/weighted.h"
#include "sim/camera_rays.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

Scene small_scene(int w = 96, int h = 72) { return testing::small_scene(w, h); }

using testing::sphere;

// testing::random_scene over a floor, at 96 x 72.
Scene random_scene(int count, unsigned seed) {
    Scene s = testing::random_scene(96, 72, count, seed, false);
    s.boxes.push_back(Box{{-5, -1.5, -5}, {5, -1, 5}, {0.3, 0.3, 0.3}});
    return s;
}

// The survey's (and McGuire & Bavoil's) equations evaluated in double precision from analytic
// ray/sphere hits: what each method must compute, overlaps and all. The scenes using it have their
// boxes behind every sphere, so C_bg is the box's radiance or the background.
Image expected_weighted(const Scene& s, WeightedMode mode) {
    const CameraRays rays = make_camera_rays(s.camera);
    const double depth_scale = WeightedMethod::weight_depth_scale(s);
    Image out(s.camera.width, s.camera.height);
    for (int j = 0; j < s.camera.height; ++j) {
        for (int i = 0; i < s.camera.width; ++i) {
            const glm::dvec3 d = rays.pixel_direction(i, j);
            const testing::OpaqueHit opaque = testing::opaque_hit(s, rays.eye, d);
            const glm::dvec3 bg = opaque.radiance;
            const glm::dvec3 ls = testing::source_radiance(s, d);
            glm::dvec3 sum_ac(0.0), sum_wac(0.0);
            double sum_a = 0.0, sum_wa = 0.0, optical_depth = 0.0, n = 0.0;
            for (const Sphere& sp : s.spheres) {
                const auto hit = testing::chord(rays.eye, d, sp, opaque.t);
                if (!hit) continue;
                const double t0 = hit->t0, t1 = hit->t1;
                const double x = sp.extinction * (t1 - t0), alpha = -std::expm1(-x);
                const glm::dvec3 c = sp.albedo * ls;
                const double z = t0 / depth_scale;
                const double w = alpha * std::clamp(0.03 / (1e-5 + z * z * z * z), 1e-2, 3e3);
                sum_ac += alpha * c;
                sum_a += alpha;
                sum_wac += w * alpha * c;
                sum_wa += w * alpha;
                optical_depth += x;
                n += 1.0;
            }
            glm::dvec3 result = bg;
            if (n > 0.0) {
                if (mode == WeightedMode::Sum) {
                    result = sum_ac + bg * (1.0 - sum_a);
                } else if (mode == WeightedMode::Average) {
                    const double t = std::pow(1.0 - sum_a / n, n);
                    result = sum_ac / sum_a * (1.0 - t) + bg * t;
                } else {
                    const double revealage = std::exp(-optical_depth);
                    result = sum_wac / sum_wa * (1.0 - revealage) + bg * revealage;
                }
            }
            for (int c = 0; c < 3; ++c) out.pixel(i, j)[c] = float(result[c]);
        }
    }
    return out;
}

const WeightedMode kModes[] = {WeightedMode::Sum, WeightedMode::Average, WeightedMode::Blended};

class Weighted : public GpuTest {};

TEST_F(Weighted, SingleSphereIsExact) {
    // One sphere per pixel has no ordering problem: every equation reduces to
    // alpha c + (1 - alpha) C_bg. A box behind (and one cutting the sphere) varies C_bg and clips chords.
    const Scene s = testing::clipped_sphere_scene();
    const glm::dvec3 centre = testing::single_sphere_radiance(s, 32, 32);
    for (WeightedMode mode : kModes) {
        WeightedMethod method(device(), mode);
        FrameStats stats;
        const Image img = method.render(s, &stats);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.pixel(32, 32)[c], centre[c], 1e-6) << method.name() << " channel " << c;
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << method.name() << ": " << describe(d);
        ASSERT_EQ(stats.passes.size(), 3u);
    }
}

TEST_F(Weighted, ThinAndDenseSingleSpheresAreExact) {
    // Optical depths from 1e-6 to 20 through one sphere on a black background: the accumulated
    // optical depth and the series keep thin spheres exact relative to their own faint image.
    for (double tau : {1e-6, 1e-3, 1.0, 10.0}) {
        Scene s = small_scene(48, 48);
        s.lighting.background = {0, 0, 0};
        s.spheres.push_back(sphere({0.1, 0, 0}, 1.0, tau, {0.3, 0.5, 0.7}));
        for (WeightedMode mode : kModes) {
            WeightedMethod method(device(), mode);
            const ImageDiff d = compare_with_reference(method.render(s, nullptr), s);
            EXPECT_EQ(d.pixels_over, 0u) << method.name() << " tau " << tau << ": " << describe(d);
        }
    }
}

TEST_F(Weighted, OverlapsFollowTheStatedEquations) {
    // Three spheres at different depths and a fourth intersecting one, overlapping on screen, over a
    // box: each method must compute its own equation (and so differ from the exact answer).
    Scene s = small_scene(80, 64);
    s.spheres.push_back(sphere({-0.3, 0.1, 1.2}, 0.6, 1.5, {0.9, 0.2, 0.2}));
    s.spheres.push_back(sphere({0.2, -0.1, -0.2}, 0.7, 0.8, {0.2, 0.9, 0.3}));
    s.spheres.push_back(sphere({0.0, 0.2, -1.8}, 0.9, 2.5, {0.2, 0.3, 0.95}));
    s.spheres.push_back(sphere({0.5, 0.4, -1.4}, 0.5, 4.0, {0.95, 0.9, 0.2}));  // intersects the third
    s.boxes.push_back(Box{{-6, -6, -9}, {6, 6, -8}, {0.35, 0.3, 0.25}});
    const Image ray_tol = reference_tolerance(s, testing::kRayRelError);
    Image tol = ray_tol;
    for (float& v : tol.rgb) v *= 4.0f;  // the equations' sensitivity to the ray, roughly the reference's
    for (WeightedMode mode : kModes) {
        WeightedMethod method(device(), mode);
        const Image img = method.render(s, nullptr);
        const ImageDiff d = compare_images(img, expected_weighted(s, mode), testing::kRelTol, &tol);
        EXPECT_EQ(d.pixels_over, 0u) << method.name() << ": " << describe(d);
        const ImageDiff vs_exact = compare_with_reference(img, s);
        EXPECT_GT(vs_exact.max_abs, 0.01 * vs_exact.peak) << method.name();
    }
}

TEST_F(Weighted, ShuffledDrawOrderGivesTheSameImage) {
    Scene s = random_scene(300, 11);
    for (WeightedMode mode : kModes) {
        WeightedMethod method(device(), mode);
        const Image a = method.render(s, nullptr);
        Scene shuffled = s;
        std::mt19937 rng(3);
        std::shuffle(shuffled.spheres.begin(), shuffled.spheres.end(), rng);
        const Image b = method.render(shuffled, nullptr);
        // Only the order of float additions changes.
        const ImageDiff d = compare_images(b, a, 1e-5);
        EXPECT_EQ(d.pixels_over, 0u) << method.name() << ": " << describe(d);
        // The scene really overlaps: the exact answer differs from this method somewhere.
        const ImageDiff vs_ref = compare_with_reference(a, s);
        EXPECT_GT(vs_ref.pixels_over, 0u) << method.name();
    }
}

TEST_F(Weighted, DarkDenseSphereInFrontOfABrightOneIsWrong) {
    // The failure mode of unsorted blending: a nearly opaque dark sphere should hide a bright one
    // behind it. wsum adds the bright one at full weight, wavg averages the two colours, wboit's depth
    // weight only partly favours the front one. Through the centre the exact answer is dark.
    Scene s = small_scene(65, 65);
    s.spheres.push_back(sphere({0, 0, 1.5}, 0.3, 15.0, {0.02, 0.02, 0.02}));  // dark, alpha ~ 1 - e^-9
    s.spheres.push_back(sphere({0, 0, -1.0}, 1.0, 8.0, {1.0, 1.0, 1.0}));    // bright, behind
    const Image ref = render_reference(s);
    double peak = 0.0;
    for (float v : ref.rgb) peak = std::max(peak, double(v));
    // ppll shows what the exact answer is at the centre: the dark sphere's radiance.
    PpllMethod ppll(device());
    const Image exact = ppll.render(s);
    EXPECT_NEAR(exact.pixel(32, 32)[0], ref.pixel(32, 32)[0], 1e-4 * peak);

    // Measured errors at the centre, relative to the peak: wsum 0.74, wavg 0.43, wboit 0.12.
    const double min_error[] = {0.5, 0.25, 0.06};
    for (WeightedMode mode : kModes) {
        WeightedMethod method(device(), mode);
        const Image img = method.render(s, nullptr);
        const double error = std::abs(double(img.pixel(32, 32)[0]) - ref.pixel(32, 32)[0]) / peak;
        EXPECT_GT(error, min_error[unsigned(mode)]) << method.name() << " error " << error;
        // It errs towards the bright sphere: too bright, never too dark.
        EXPECT_GT(img.pixel(32, 32)[0], ref.pixel(32, 32)[0]) << method.name();
        // Where only the bright sphere is seen, the method is exact again.
        EXPECT_NEAR(img.pixel(32, 20)[1], ref.pixel(32, 20)[1], 1e-4 * peak) << method.name();
    }
}

TEST_F(Weighted, WboitDepthScaleFollowsTheScene) {
    Scene s = small_scene();
    s.spheres.push_back(sphere({0, 0, 0}, 1.0, 1.0));
    EXPECT_NEAR(WeightedMethod::weight_depth_scale(s), 6.0 / 1.32, 1e-12);  // farthest point: 5 + 1
    s.spheres.push_back(sphere({0, 0, -20}, 2.0, 0.0));                       // no extinction: ignored
    EXPECT_NEAR(WeightedMethod::weight_depth_scale(s), 6.0 / 1.32, 1e-12);
    EXPECT_EQ(WeightedMethod::weight_depth_scale(small_scene()), 1.0);
}

TEST_F(Weighted, FactoriesRejectSettings) {
    // Called directly, not through the registry; the names and exactness: test_gpu_methods.cpp.
    EXPECT_THROW(make_wsum_method(device(), "4"), std::invalid_argument);
    EXPECT_THROW(make_wavg_method(device(), "x"), std::invalid_argument);
    EXPECT_THROW(make_wboit_method(device(), "1"), std::invalid_argument);
}

}  // namespace
}  // namespace brume
