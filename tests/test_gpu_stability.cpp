// The stability suite (issue 4): the scenes where methods break. On each, ppll must stay exact or
// report exactly what it could not do; every other method must run, stay finite and keep the
// validation layer quiet, and its error against the reference is recorded (printed and stored as a
// test property), not asserted: how a baseline degrades is what `brume bench` charts.
#include "gpu_test_env.h"
#include "render/methods/registry.h"
#include "render/methods/ppll.h"
#include "sim/layers_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

Sphere sphere(glm::dvec3 c, double r, double tau, glm::dvec3 albedo = {0.8, 0.8, 0.85}) {
    Sphere s;
    s.center = c;
    s.radius = r;
    s.extinction = tau;
    s.albedo = albedo;
    return s;
}

Scene small_scene() {
    Scene s;
    s.camera.position = {0.0, 0.4, 5.0};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.width = 64;
    s.camera.height = 48;
    s.render.min_transmittance = 0.0;
    return s;
}

const std::vector<std::string> kBaselines = {"auto",   "sorted", "soft",   "wsum",         "wavg",
                                             "wboit",  "kbuf",   "peel",   "peel:dual:8",  "stochastic:4",
                                             "screendoor:2"};

class Stability : public GpuTest {
protected:
    // ppll exact against the reference; every baseline finite, its error recorded.
    void run_all(const Scene& scene, const std::string& label) {
        PpllMethod ppll(device());
        FrameStats stats;
        const Image exact = ppll.render(scene, &stats);
        const ImageDiff d = compare_with_reference(exact, scene);
        EXPECT_EQ(d.pixels_over, 0u) << label << ": " << describe(d);
        const Image ref = render_reference(scene);
        for (const std::string& spec : kBaselines) {
            auto method = make_method(&device(), spec);
            const Image img = method->render(scene, nullptr);
            const bool finite =
                std::all_of(img.rgb.begin(), img.rgb.end(), [](float v) { return std::isfinite(v); });
            EXPECT_TRUE(finite) << spec << " on " << label;
            const ImageDiff e = compare_images(img, ref, 0.0);
            const double rmse = e.peak > 0 ? e.rmse / e.peak : e.rmse;
            std::printf("  %-14s %-22s rmse/peak %.3g  max/peak %.3g\n", spec.c_str(), label.c_str(), rmse,
                        e.peak > 0 ? e.max_abs / e.peak : e.max_abs);
            RecordProperty(spec + "_rmse_over_peak", std::to_string(rmse));
        }
    }
};

TEST_F(Stability, TwoHundredFiftySixSurfacesPerPixel) {
    const Scene s = make_layers_scene(256, 64, 48);  // 128 spheres enclosing the view
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(s, &stats);
    EXPECT_EQ(stats.max_list_length, 128u);
    EXPECT_EQ(stats.fragments, 64u * 48u * 128u);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    run_all(s, "256 layers");
}

TEST_F(Stability, PoolOverflowRegrowsOrReportsTheBytes) {
    Scene s = small_scene();
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 300; ++k) s.spheres.push_back(sphere({u(rng), u(rng), u(rng)}, 0.4, 1.0));
    PpllOptions tiny_first;
    tiny_first.initial_nodes = 8;
    PpllMethod grows(device(), tiny_first);
    FrameStats stats;
    const ImageDiff d = compare_with_reference(grows.render(s, &stats), s);
    EXPECT_GE(stats.regrows, 1);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    PpllOptions capped;
    capped.max_pool_bytes = 16 * 1024;
    PpllMethod refuses(device(), capped);
    EXPECT_THROW(refuses.render(s), PoolBudgetError);
}

TEST_F(Stability, CoincidentAndTangentSpheres) {
    Scene s = small_scene();
    for (int k = 0; k < 6; ++k) s.spheres.push_back(sphere({0, 0, 0}, 0.8, 0.5 + k * 0.3, {0.9 - 0.1 * k, 0.5, 0.3 + 0.1 * k}));
    s.spheres.push_back(sphere({1.6, 0, 0}, 0.8, 2.0));   // tangent to all of them
    s.spheres.push_back(sphere({-1.2, 0, 0}, 0.4, 2.0));  // tangent from the other side
    run_all(s, "coincident+tangent");
}

TEST_F(Stability, EyeInsideMediaAndCrossingTheEyePlane) {
    Scene s = small_scene();
    s.camera.position = {0.0, 0.0, 0.0};
    s.camera.look_at = {0.0, 0.0, -1.0};
    s.spheres.push_back(sphere({0.1, 0.0, 0.2}, 1.5, 0.6));
    s.spheres.push_back(sphere({0.5, 0.2, -0.5}, 1.0, 1.2, {0.3, 0.6, 0.9}));
    s.spheres.push_back(sphere({-0.9, 0.0, 0.3}, 0.7, 2.0, {0.9, 0.5, 0.2}));  // cut by the eye plane
    s.spheres.push_back(sphere({0.0, 0.0, -3.0}, 0.6, 3.0));
    run_all(s, "eye inside media");
}

TEST_F(Stability, ExtinctionFromOneMillionthToTenThousand) {
    Scene s = small_scene();
    const double taus[] = {1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4};
    for (int k = 0; k < 6; ++k) s.spheres.push_back(sphere({-1.5 + 0.6 * k, 0.1 * k, -0.2 * k}, 0.45, taus[k]));
    run_all(s, "extinction 1e-6..1e4");
}

TEST_F(Stability, SubPixelParticles) {
    // Particles far smaller than a pixel: only those a pixel-centre ray meets exist for the image.
    Scene s = small_scene();
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 5000; ++k) s.spheres.push_back(sphere({2 * u(rng), 1.5 * u(rng), u(rng)}, 0.004, 50.0));
    run_all(s, "sub-pixel particles");
}

TEST_F(Stability, ParticlesCutByBoxes) {
    Scene s = small_scene();
    s.boxes.push_back(Box{{-3, -2, -0.1}, {3, -0.2, 0.1}, {0.6, 0.2, 0.1}});
    s.boxes.push_back(Box{{0.3, -2, -2}, {0.5, 2, 2}, {0.1, 0.4, 0.2}});
    for (int k = 0; k < 10; ++k) s.spheres.push_back(sphere({-1.0 + 0.25 * k, 0.1 * (k % 3), 0.1 * (k % 4)}, 0.5, 1.5));
    run_all(s, "cut by boxes");
}

TEST_F(Stability, OneMillionParticles) {
    // A million small particles in a slab: ppll exact against the reference; the baselines are
    // only required to cope (memory, sorting a million keys) without error.
    Scene s = small_scene();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    s.spheres.reserve(1000000);
    for (int k = 0; k < 1000000; ++k)
        s.spheres.push_back(sphere({2.2 * u(rng), 1.6 * u(rng), 0.5 * u(rng)}, 0.01, 20.0, {0.9, 0.9, 0.9}));
    run_all(s, "1 million particles");
}

}  // namespace
}  // namespace brume
