// kbuf (FreePipe / k-buffer: Maule, "Survey on Order Independent Transparency Techniques", sections
// 2.5 and 4.2): exact for up to k non-intersecting spheres per pixel, and within the stated tail bound
// beyond k.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/kbuffer.h"
#include "sim/camera_rays.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

Scene small_scene(int w = 80, int h = 64) { return testing::small_scene(w, h); }

using testing::sphere;

// `count` spheres one behind another (radius 0.45, centres 1 apart in depth: they never intersect),
// jittered sideways so their silhouettes differ, all overlapping the centre of the view. Listed in
// a shuffled order so the draw order is not the depth order.
Scene stack_scene(int count, unsigned seed) {
    Scene s = small_scene();
    s.camera.position = {0.0, 0.0, 4.0};
    s.camera.fov_y_deg = 30.0;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < count; ++i)
        s.spheres.push_back(sphere({u(rng) * 0.4 - 0.2, u(rng) * 0.4 - 0.2, 1.5 - 1.0 * i}, 0.45, 0.3 + 2.0 * u(rng),
                                   {u(rng), u(rng), u(rng)}));
    std::shuffle(s.spheres.begin(), s.spheres.end(), rng);
    s.boxes.push_back(Box{{-9, -9, -40}, {9, 9, -39}, {0.4, 0.5, 0.6}});
    return s;
}

// The stated tail bound per pixel and channel, T_k * alpha_tail * (max_tail c - min_tail c), from
// double-precision intersections of the pixel ray with every sphere (the scenes here have no box in
// front of a sphere, so no clipping by opaque surfaces).
Image tail_bound(const Scene& s, int k) {
    const CameraRays rays = make_camera_rays(s.camera);
    Image bound(s.camera.width, s.camera.height);
    for (int j = 0; j < s.camera.height; ++j) {
        for (int i = 0; i < s.camera.width; ++i) {
            const glm::dvec3 d = rays.pixel_direction(i, j);
            struct Hit {
                double t0, alpha;
                glm::dvec3 color;
            };
            std::vector<Hit> hits;
            const glm::dvec3 ls = testing::source_radiance(s, d);
            for (const Sphere& sp : s.spheres)
                if (const auto c = testing::chord(rays.eye, d, sp))
                    hits.push_back({c->t0, -std::expm1(-sp.extinction * (c->t1 - c->t0)), sp.albedo * ls});
            std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t0 < b.t0; });
            if (int(hits.size()) <= k) continue;
            double transmittance = 1.0, tail_transmittance = 1.0;
            glm::dvec3 lo(1e30), hi(-1e30);
            for (int h = 0; h < int(hits.size()); ++h) {
                if (h < k) {
                    transmittance *= 1.0 - hits[h].alpha;
                } else {
                    tail_transmittance *= 1.0 - hits[h].alpha;
                    lo = glm::min(lo, hits[h].color);
                    hi = glm::max(hi, hits[h].color);
                }
            }
            for (int c = 0; c < 3; ++c) bound.pixel(i, j)[c] = float(transmittance * (1.0 - tail_transmittance) * (hi[c] - lo[c]));
        }
    }
    return bound;
}

class KBuffer : public GpuTest {};

TEST_F(KBuffer, SingleSphereIsExact) {
    const Scene s = testing::clipped_sphere_scene();
    for (std::uint32_t k : {1u, 8u}) {
        KBufferMethod method(device(), k);
        FrameStats stats;
        const ImageDiff d = compare_with_reference(method.render(s, &stats), s);
        EXPECT_EQ(d.pixels_over, 0u) << method.name() << ": " << describe(d);
        ASSERT_EQ(stats.passes.size(), 4u);
        EXPECT_EQ(stats.memory_bytes, 65u * 65u * (12u * k + 20u));
    }
}

TEST_F(KBuffer, UpToKNonIntersectingSpheresAreExact) {
    for (std::uint32_t k : {1u, 4u, 8u, 32u}) {
        for (int count : {int(k), int(k) / 2}) {
            if (count == 0) continue;
            const Scene s = stack_scene(count, 100 + k);
            KBufferMethod method(device(), k);
            const ImageDiff d = compare_with_reference(method.render(s, nullptr), s);
            EXPECT_EQ(d.pixels_over, 0u) << method.name() << ", " << count << " spheres: " << describe(d);
        }
    }
}

TEST_F(KBuffer, EarlyTerminationMatchesTheReference) {
    // Dense spheres drive the transmittance below the scene's threshold: kbuf stops where the
    // reference does and adds nothing behind.
    Scene s = stack_scene(6, 7);
    for (Sphere& sp : s.spheres) sp.extinction *= 4.0;
    s.render.min_transmittance = 1e-2;
    KBufferMethod method(device(), 8);
    const ImageDiff d = compare_with_reference(method.render(s, nullptr), s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(KBuffer, BeyondKTheErrorStaysWithinTheTailBound) {
    const int k = 3, count = 8;
    const Scene s = stack_scene(count, 21);
    KBufferMethod method(device(), k);
    const Image img = method.render(s, nullptr);
    const Image ref = render_reference(s);
    const Image ray_tol = reference_tolerance(s, testing::kRayRelError);
    const Image bound = tail_bound(s, k);
    double peak = 0.0;
    for (float v : ref.rgb) peak = std::max(peak, double(v));
    std::size_t over = 0, beyond_k = 0;
    double worst = 0.0, largest_error = 0.0, largest_bound = 0.0;
    for (std::size_t i = 0; i < ref.rgb.size(); ++i) {
        const double error = std::abs(double(img.rgb[i]) - ref.rgb[i]);
        const double allowed = bound.rgb[i] + ray_tol.rgb[i] + testing::kRelTol * peak;
        if (error > allowed) ++over;
        worst = std::max(worst, error - allowed);
        largest_error = std::max(largest_error, error);
        largest_bound = std::max(largest_bound, double(bound.rgb[i]));
        if (bound.rgb[i] > 0.0f) ++beyond_k;
    }
    EXPECT_EQ(over, 0u) << "worst excess " << worst;
    ASSERT_GT(beyond_k, 100u) << "the scene must put more than k spheres on many pixels";
    // The tail approximation is really at work: kbuf is not exact here, and the bound is not vacuous.
    EXPECT_GT(largest_error, 5.0 * testing::kRelTol * peak);  // measured: 9.4e-4, bound up to 8.3e-3, peak 0.6
    EXPECT_LT(largest_bound, 0.5 * peak);
    // With k = count the same scene is exact.
    KBufferMethod all(device(), count);
    const ImageDiff d = compare_with_reference(all.render(s, nullptr), s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(KBuffer, EyeInsideSpheresIsOrderedAndFinite) {
    // Spheres containing the eye all start at distance 0: their keys are their (negative) unclipped
    // entries, so the result does not depend on draw order.
    Scene s = small_scene();
    s.camera.position = {0.1, 0.0, 0.2};
    s.spheres.push_back(sphere({0, 0, 0}, 1.5, 0.4, {0.9, 0.9, 0.9}));
    s.spheres.push_back(sphere({0.3, 0.2, 0.1}, 0.8, 1.0, {0.3, 0.6, 0.9}));
    s.spheres.push_back(sphere({0, 0, -2}, 2.5, 0.5, {0.9, 0.5, 0.2}));
    s.spheres.push_back(sphere({0, 0, -3}, 0.5, 2.0));
    KBufferMethod method(device(), 2);
    const Image a = method.render(s, nullptr);
    std::reverse(s.spheres.begin(), s.spheres.end());
    const Image b = method.render(s, nullptr);
    EXPECT_TRUE(testing::all_finite(a));
    const ImageDiff d = compare_images(b, a, 1e-5);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(KBuffer, SettingsParse) {
    EXPECT_EQ(parse_kbuf_setting(""), 8u);
    EXPECT_EQ(parse_kbuf_setting("1"), 1u);
    EXPECT_EQ(parse_kbuf_setting("32"), 32u);
    for (const char* bad : {"0", "33", "x", "-1", "8.5", "0008", " 8"})
        EXPECT_THROW(parse_kbuf_setting(bad), std::invalid_argument) << bad;
    // The names of the catalogued settings: test_gpu_methods.cpp.
    EXPECT_EQ(make_kbuf_method(device(), "1")->name(), "kbuf:1");
    EXPECT_THROW(make_kbuf_method(device(), "40"), std::invalid_argument);
}

}  // namespace
}  // namespace brume
