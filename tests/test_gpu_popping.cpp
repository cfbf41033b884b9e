// Popping regression tests: animated scenes where the order of particles flips. The temporal error
// (temporal_error, render/image_compare.h) of every exact method of the catalogue (ppll, ppll-general, auto) stays at
// the reference's floor; the sorted baseline, on the very same frames, exceeds a threshold many times
// larger, which shows the metric can fail.
#include "gpu_test_env.h"
#include "test_scenes.h"
#include "render/methods/registry.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"

#include <cmath>
#include <random>

namespace brume {
namespace {

using testing::GpuTest;
using testing::sphere;

constexpr double kExactBound = 1e-4;    // exact methods: at most 1e-4 of the peak per frame step
constexpr double kPoppingFloor = 5e-4;  // sorted must exceed this somewhere: 5x the exact bound
constexpr double kPlainJump = 0.15;     // a jump of 15% of the peak in one frame step: plainly visible

Scene base_scene() {
    Scene s;
    s.camera.position = {0.0, 0.3, 5.0};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.width = 96;
    s.camera.height = 72;
    s.lighting.background = {0.1, 0.1, 0.12};
    return s;
}

// Largest temporal error of `method` over the frames.
double max_temporal_error(Method& method, const std::vector<Scene>& frames, const std::vector<Image>& refs) {
    double worst = 0.0;
    Image prev;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        Image img = method.render(frames[f], nullptr);
        if (f > 0) worst = std::max(worst, temporal_error(img, prev, refs[f], refs[f - 1]));
        prev = std::move(img);
    }
    return worst;
}

class Popping : public GpuTest {
protected:
    void check(const std::vector<Scene>& frames) {
        std::vector<Image> refs;
        // A preset with per-sphere shadows (crossing) is compared with the reference's per-sphere mode,
        // for which the exact methods are exact: popping is about order, and the exact shadows would
        // cost the reference O(pixels x spheres) a frame.
        for (const Scene& s : frames) {
            ReferenceOptions options;
            if (s.lighting.shadows && s.render.shadow_technique == ShadowTechnique::PerSphere)
                options.shadows = ReferenceShadows::PerSphere;
            refs.push_back(render_reference(s, options));
        }
        auto sorted = make_method(&device(), "sorted");
        const double popping = max_temporal_error(*sorted, frames, refs);
        EXPECT_GT(popping, kPoppingFloor) << "the sorted baseline should pop on these frames: sorted " << popping;
        int exact_methods = 0;
        for (const MethodEntry& entry : method_catalogue()) {
            if (!entry.exact || !entry.needs_device) continue;  // the reference is the floor itself
            ++exact_methods;
            auto method = make_method(&device(), entry.name);
            const double exact = max_temporal_error(*method, frames, refs);
            char figures_text[128];
            std::snprintf(figures_text, sizeof figures_text, "%s %.3g, sorted %.3g", entry.name.c_str(), exact, popping);
            const std::string figures = figures_text;
            EXPECT_LE(exact, kExactBound) << figures;
            EXPECT_GT(popping, 1000.0 * exact) << figures;
            std::printf("max temporal error: %s\n", figures.c_str());
        }
        EXPECT_GE(exact_methods, 1);
    }
};

TEST_F(Popping, ParticlePassingThroughAnother) {
    std::vector<Scene> frames;
    for (int f = 0; f < 24; ++f) {
        Scene s = base_scene();
        s.spheres.push_back(sphere({0.0, 0.0, 0.0}, 0.8, 2.0, {0.9, 0.3, 0.2}));
        const double z = -2.0 + 4.0 * f / 23.0;  // through the first sphere, towards the eye
        s.spheres.push_back(sphere({0.15, 0.1, z}, 0.6, 3.0, {0.2, 0.4, 0.95}));
        frames.push_back(s);
    }
    check(frames);
}

TEST_F(Popping, CameraOrbitingACluster) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Sphere> cluster;
    for (int k = 0; k < 30; ++k)
        cluster.push_back(sphere({u(rng), 0.6 * u(rng), u(rng)}, 0.35 + 0.15 * u(rng), 2.0 + 1.5 * u(rng),
                                 {0.6 + 0.3 * u(rng), 0.6 + 0.3 * u(rng), 0.6 + 0.3 * u(rng)}));
    std::vector<Scene> frames;
    for (int f = 0; f < 24; ++f) {
        Scene s = base_scene();
        const double a = f * 3.14159265358979 / 48.0;  // 90 degrees over the sequence
        s.camera.position = {4.5 * std::sin(a), 0.8, 4.5 * std::cos(a)};
        s.spheres = cluster;
        frames.push_back(s);
    }
    check(frames);
}

TEST_F(Popping, TwoStreamsCrossing) {
    const std::optional<Preset> preset = builtin_preset("crossing");
    ASSERT_TRUE(preset);
    Simulator sim(*preset);
    sim.advance_to_frame(preset->timeline.frame_count() / 3);
    std::vector<Scene> frames;
    for (int f = 0; f < 24; ++f) {
        if (f > 0) sim.step_frame();
        Scene s = preset->scene;
        sim.append_spheres(s.spheres);
        s.camera = camera_at(*preset, sim.time());
        s.camera.fov_y_deg /= 4.0;  // zoom onto the crossing, so that its pops are not a few pixels of 96x72
        s.camera.width = 96;
        s.camera.height = 72;
        frames.push_back(s);
    }
    check(frames);
}

// Pixels where a frame step of `now` against `prev` differs from the reference's own step by more than
// `fraction` of the reference's peak, in some channel: what a viewer sees jump.
int popped_pixels(const Image& now, const Image& prev, const Image& ref_now, const Image& ref_prev, double fraction) {
    float peak = 0.0f;
    for (const float v : ref_now.rgb) peak = std::max(peak, v);
    int count = 0;
    for (std::size_t p = 0; p < now.rgb.size(); p += 3) {
        bool jumped = false;
        for (std::size_t c = 0; c < 3; ++c)
            jumped |= std::abs((now.rgb[p + c] - prev.rgb[p + c]) - (ref_now.rgb[p + c] - ref_prev.rgb[p + c])) >
                      fraction * peak;
        count += jumped;
    }
    return count;
}

// The `pop` preset is the README's "watch it pop": sorted must pop there plainly, over a large part of
// the frame in one step, where the exact methods do not pop at all (and check() holds them to the
// reference's floor, as on every popping scene).
TEST_F(Popping, PopPresetPopsPlainlyWithSortedOnly) {
    const std::optional<Preset> preset = builtin_preset("pop");
    ASSERT_TRUE(preset);
    Simulator sim(*preset);
    std::vector<Scene> frames;
    for (int f = 0; f < 16; ++f) {  // one meeting of the lanes, at frame 3 (one every 12 frames)
        if (f > 0) sim.step_frame();
        Scene s = preset->scene;
        sim.append_spheres(s.spheres);
        s.camera = camera_at(*preset, sim.time());
        s.camera.width = 96;
        s.camera.height = 72;
        frames.push_back(s);
    }
    check(frames);
    std::vector<Image> refs;
    for (const Scene& s : frames) {
        ReferenceOptions options;
        options.shadows = ReferenceShadows::PerSphere;
        refs.push_back(render_reference(s, options));
    }
    const int pixels = 96 * 72;
    for (const char* name : {"sorted", "ppll"}) {
        auto method = make_method(&device(), name);
        int most = 0;
        Image prev;
        for (std::size_t f = 0; f < frames.size(); ++f) {
            Image img = method->render(frames[f], nullptr);
            if (f > 0) most = std::max(most, popped_pixels(img, prev, refs[f], refs[f - 1], kPlainJump));
            prev = std::move(img);
        }
        std::printf("%s: at most %d of %d pixels jump by over %.2f of the peak in one frame step\n", name, most,
                    pixels, kPlainJump);
        if (std::string(name) == "sorted")
            EXPECT_GT(most, pixels / 25) << "sorted should pop plainly on pop: over 4% of the frame at once";
        else
            EXPECT_EQ(most, 0) << name << " is exact: nothing may jump against the reference";
    }
}

}  // namespace
}  // namespace brume
