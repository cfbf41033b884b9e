// Every shipped preset simulates and renders; ppll matches the reference on real simulated frames (with
// their shadows, fire and lit ground), including the fog bank whose camera flies through the particles
// and the cloud read from a density grid.
#include "gpu_test_env.h"
#include "render/methods/ppll.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

class Presets : public GpuTest, public ::testing::WithParamInterface<std::string> {};

Scene frame_scene(const Preset& preset, Simulator& sim, int frame) {
    sim.advance_to_frame(frame);
    Scene scene = preset.scene;
    sim.append_spheres(scene.spheres);
    scene.camera = camera_at(preset, sim.time());
    scene.camera.width = 64;
    scene.camera.height = 48;
    return scene;
}

TEST_P(Presets, SimulatedFrameMatchesReference) {
    std::optional<Preset> preset = builtin_preset(GetParam());
    ASSERT_TRUE(preset.has_value());
    prepare_preset(*preset);  // [[vdb]] volumes to spheres, density emitters' grids
    Simulator sim(*preset);
    // A frame a third of the way in: emitters have filled the view, the fog-bank camera is moving.
    const int frame = preset->timeline.frame_count() / 3;
    const Scene scene = frame_scene(*preset, sim, frame);
    PpllMethod ppll(device());
    FrameStats stats;
    const Image img = ppll.render(scene, &stats);
    if (GetParam() != "layers") {
        EXPECT_GT(sim.size(), 0u) << "nothing was emitted by frame " << frame;
    }
    EXPECT_GT(stats.fragments, 0u);
    // Presets shade their shadows by the per-sphere technique, for which ppll is exact: the reference is
    // asked for the same technique (its exact model is the issue's, checked in test_gpu_light.cpp).
    ReferenceOptions options;
    if (scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::PerSphere)
        options.shadows = ReferenceShadows::PerSphere;
    const ImageDiff d = compare_with_reference(img, testing::ReferenceImage(scene, options));
    EXPECT_EQ(d.pixels_over, 0u) << GetParam() << " frame " << frame << ": " << describe(d);
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
