// Every shipped preset simulates and renders; ppll matches the reference on real simulated frames (with
// their shadows, fire and lit ground), including the fog bank whose camera flies through the particles
// and the cloud read from a density grid; each shadow technique stays within its stated error of the
// exact model on every shadowed preset.
#include "gpu_test_env.h"
#include "shadow_error.h"
#include "render/fast_tracer.h"
#include "render/methods/ppll.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

class Presets : public GpuTest, public ::testing::WithParamInterface<std::string> {};

Scene frame_scene(const Preset& preset, Simulator& sim, int frame, int width = 64, int height = 48) {
    sim.advance_to_frame(frame);
    Scene scene = preset.scene;
    sim.append_spheres(scene.spheres);
    scene.camera = camera_at(preset, sim.time());
    scene.camera.width = width;
    scene.camera.height = height;
    return scene;
}

TEST_P(Presets, SimulatedFrameMatchesReference) {
    std::optional<Preset> preset = builtin_preset(GetParam());
    ASSERT_TRUE(preset.has_value());
    prepare_preset(*preset);  // [[vdb]] volumes to spheres, density emitters' grids
    Simulator sim(*preset);
    // A frame a third of the way in: emitters have filled the view, the fog-bank camera is moving.
    const int frame = preset->timeline.frame_count() / 3;
    Scene scene = frame_scene(*preset, sim, frame);
    // ppll is exact for the per-sphere technique (the accurate one is checked below, against the exact
    // model): a preset that uses the accurate one is checked here by the per-sphere one.
    if (scene.lighting.shadows) scene.render.shadow_technique = ShadowTechnique::PerSphere;
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(scene, &stats);
    if (GetParam() != "layers") {
        EXPECT_GT(sim.size(), 0u) << "nothing was emitted by frame " << frame;
    }
    EXPECT_GT(stats.fragments, 0u);
    // The reference is asked for the same technique (its exact model is the issue's, checked in
    // test_gpu_light.cpp and below).
    ReferenceOptions options;
    if (scene.lighting.shadows) options.shadows = ReferenceShadows::PerSphere;
    const ImageDiff d = compare_with_reference(img, testing::ReferenceImage(scene, options));
    EXPECT_EQ(d.pixels_over, 0u) << GetParam() << " frame " << frame << ": " << describe(d);
}

// The error of each shadow technique against the exact model on the presets' frames, as measured at
// 32x24 (docs/accuracy.md, "The shipped presets"), with headroom. These are larger than on the test
// clouds of test_gpu_light.cpp: the accurate technique's map is trilinear between vertices 0.09 of a
// mean radius apart, furthest off in dense, fine smoke (plume p99.9 1.4e-2 by both paths, explosion
// 8e-3; before trace's pieces were refined and ppll's long pieces halved, 2.0e-2 and 1.2-1.7e-2; at
// 32x24 p99.9 is the worst pixel or two; the target, 1e-2, both meet at 128x96; the mean at
// most 2.3e-4). Box shadows are cut out of each segment exactly by
// both paths, so a low sun's sharp shadows across long fog segments no longer show (low-sun p99.9
// 1.5e-3 by ppll; 2.4e-2 when ppll's quadrature straddled them). The per-sphere technique's constant
// T_sun per sphere is furthest off in wide, thin fog (ground-fog, mean 2.1e-2). Each technique must
// also be nearer the model than no shadows at all.
constexpr double kAccurateMean = 1e-3, kAccurateP999 = 1.8e-2;
constexpr double kPerSphereMean = 3e-2, kPerSphereP999 = 0.3;
constexpr double kTraceAccurateMean = 1e-3, kTraceAccurateP999 = 1.8e-2;

// Each preset's own p99.9 of the accurate technique at the test's size, as measured (trace, ppll), so
// that a regression on one preset shows even where it stays under the common bound above (ppll's
// explosion read 1.7e-2 with its old one 3-point rule per lit piece; since thin media's pieces may
// run longer, kSunPieceThinWiden, and their map's spacing widens, thin_media_widening, crossing reads
// 7.2e-3, low-sun 5.9e-3, ground-fog 5.0e-3 and vdb-cloud 3.7e-3 (at 16x12), against 1.5e-3, 2.0e-3, 3.3e-3 and
// 2.0e-3 before). ppll and tiles integrate as
// trace does (shaders/exact_integrator.glsl), so the two read the same to float rounding. The bound is 1.5x the
// figure, and at least 1e-3 (float rounding between drivers); a preset missing here has the common
// bound only.
struct MeasuredP999 {
    const char* preset;
    double trace, ppll;
};
constexpr MeasuredP999 kMeasuredAccurateP999[] = {
    {"campfire", 6.1e-4, 6.1e-4},  {"crossing", 7.23e-3, 7.23e-3},  {"explosion", 8.33e-3, 8.33e-3},
    {"fog-bank", 1.17e-3, 1.17e-3}, {"ground-fog", 5.04e-3, 5.04e-3}, {"low-sun", 5.87e-3, 5.87e-3},
    {"plume", 1.45e-2, 1.45e-2},   {"pop", 2.96e-3, 2.96e-3},     {"vdb-cloud", 6.08e-3, 6.08e-3},
};
double accurate_p999_bound(const std::string& preset, bool trace) {
    for (const MeasuredP999& m : kMeasuredAccurateP999)
        if (preset == m.preset) return std::min(std::max(1.5 * (trace ? m.trace : m.ppll), 1e-3), trace ? kTraceAccurateP999 : kAccurateP999);
    return trace ? kTraceAccurateP999 : kAccurateP999;
}

// Both techniques against the exact model on the preset's frame, at 32x24: the exact reference's shadows
// cost seconds a frame at full size (vdb-cloud 37 s at 640x360, 0.2 s here), which is why this runs small.
// (vdb-cloud ran at 16x12, p99.9 3.66e-3, until the reference took its shadows in sets between kinks.) On lavapipe the accurate technique's sun lookups can exceed the device's loop budget
// on the densest smoke (vdb-cloud; plume at full size): the frame is then refused by name (ListResolveError), never wrong.
TEST_P(Presets, ShadowTechniquesWithinTheirStatedErrorOfTheExactModel) {
    std::optional<Preset> preset = builtin_preset(GetParam());
    ASSERT_TRUE(preset.has_value());
    if (!preset->scene.lighting.shadows) GTEST_SKIP() << GetParam() << " has no shadows (the benchmark scene)";
    prepare_preset(*preset);
    Simulator sim(*preset);
    const int frame = preset->timeline.frame_count() / 3;
    Scene scene = frame_scene(*preset, sim, frame, 32, 24);
    const Image exact = render_reference(scene);
    PpllMethod ppll(device());
    Scene off = scene;
    off.lighting.shadows = false;
    const testing::ShadowError none = testing::shadow_error(ppll.render(off), exact);
    scene.render.shadow_technique = ShadowTechnique::PerSphere;
    const testing::ShadowError per_sphere = testing::shadow_error(ppll.render(scene), exact);
    std::printf("  %s frame %d, %dx%d, error of the peak: per-sphere mean %.3g p99.9 %.3g; no shadows mean %.3g "
                "p99.9 %.3g\n",
                GetParam().c_str(), frame, scene.camera.width, scene.camera.height, per_sphere.mean, per_sphere.p999,
                none.mean, none.p999);
    EXPECT_LT(per_sphere.mean, kPerSphereMean);
    EXPECT_LT(per_sphere.p999, kPerSphereP999);
    EXPECT_LT(per_sphere.mean, none.mean) << "the shadows should be seen";
    scene.render.shadow_technique = ShadowTechnique::Accurate;
    // trace's accurate technique (the light-space depth map, render/sun_depth_map.h): what auto renders
    // shadowed frames with on a CPU device.
    const testing::ShadowError traced = testing::shadow_error(render_fast_trace(scene), exact);
    std::printf("  trace accurate mean %.3g p99.9 %.3g\n", traced.mean, traced.p999);
    EXPECT_LT(traced.mean, kTraceAccurateMean);
    EXPECT_LT(traced.p999, accurate_p999_bound(GetParam(), true));
    EXPECT_LT(traced.mean, per_sphere.mean);
    try {
        const testing::ShadowError accurate = testing::shadow_error(ppll.render(scene), exact);
        std::printf("  accurate mean %.3g p99.9 %.3g\n", accurate.mean, accurate.p999);
        EXPECT_LT(accurate.mean, kAccurateMean);
        EXPECT_LT(accurate.p999, accurate_p999_bound(GetParam(), false));
        EXPECT_LT(accurate.mean, per_sphere.mean);
    } catch (const ListResolveError& e) {
        std::printf("  accurate refused: %s\n", e.what());
        EXPECT_TRUE(GetParam() == "plume" || GetParam() == "vdb-cloud") << "refused where it was not before: " << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(Shipped, Presets, ::testing::ValuesIn(builtin_preset_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (c == '-') c = '_';
                             return name;
                         });

}  // namespace
}  // namespace brume
