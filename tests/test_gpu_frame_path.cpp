// The frame path (render/frame/frame_path.h): one path for every method, several methods through
// one path, the overflow loop and steps, the tone-map pass a window shows against the PNG writer,
// and the device names users type. Presentation to a window: tests/test_window_swapchain.cpp.
#include "gpu_test_env.h"
#include "test_scenes.h"

#include "render/frame/frame_path.h"
#include "render/frame/offscreen_presenter.h"
#include "render/image_io.h"
#include "render/methods/peel.h"
#include "render/methods/ppll.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "render/vk/vk_check.h"
#include "sim/builtin_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace brume {
namespace {

using testing::GpuTest;
using testing::same_bits;
using testing::small_scene;
using testing::sphere;

Scene overlapping_scene() { return testing::overlapping_scene(48, 36); }

class FramePathTest : public GpuTest {};

// One frame path serves methods one after another (as a preview switching methods does): each
// frame is bit for bit what the method renders through its own path. Every GPU method of the
// catalogue, at its default setting and at the settings `brume bench` sweeps.
TEST_F(FramePathTest, SharedPathMatchesEachMethodsOwnPath) {
    const Scene scene = overlapping_scene();
    FramePath path(device());
    for (const std::string& spec : bench_method_specs()) {
        if (!find_method(spec).needs_device) continue;
        auto own = make_method(&device(), spec);
        auto shared = make_method(&device(), spec);
        const Image expected = own->render(scene);
        const Image via_shared = path.render(*shared->gpu(), scene);
        EXPECT_TRUE(same_bits(expected, via_shared)) << spec;
    }
    // And back to the first, after the path held other methods' bindings.
    auto ppll = make_method(&device(), "ppll");
    EXPECT_TRUE(same_bits(make_method(&device(), "ppll")->render(scene), path.render(*ppll->gpu(), scene)));
}

// The overflow loop lives in the frame path: a pool too small regrows and the frame is rendered
// again, counted in FrameStats, and the image is still exact.
TEST_F(FramePathTest, OverflowRendersTheFrameAgainAndCountsIt) {
    Scene scene = overlapping_scene();
    scene.camera.width = 128;  // several thousand fragments: more than the smallest pool (1,024)
    scene.camera.height = 96;
    PpllOptions options;
    options.initial_nodes = 16;
    PpllMethod ppll(device(), options);
    FrameStats stats;
    const Image image = ppll.render(scene, &stats);
    EXPECT_GE(stats.regrows, 1);
    EXPECT_GT(stats.pool_capacity, 16u);
    EXPECT_EQ(testing::compare_with_reference(image, scene).pixels_over, 0u);
    // The frame path's shared pass is the first GPU pass (after the CPU sort ppll lists first);
    // the total is the sum of the passes.
    ASSERT_GE(stats.passes.size(), 2u);
    EXPECT_EQ(stats.passes[0].name, "sort (cpu)");
    EXPECT_EQ(stats.passes[1].name, "clear+opaque");
    double sum = 0.0;
    for (const PassTime& p : stats.passes) sum += p.ms;
    EXPECT_DOUBLE_EQ(stats.total_ms, sum);
}

// The light's CPU preparation is part of a GPU frame's cost: the sun grid (the lit ground's exact
// T_sun), the per-sphere T_sun at the centres, and the accurate technique's depth map are listed as
// "(cpu)" passes after the method's sort and before the GPU passes, each only in the frames that
// build it, and the total counts them (a shadow technique's cost against the unshadowed frame, as
// bench shadows takes it, included the GPU passes alone before).
TEST_F(FramePathTest, TheLightsCpuPreparationIsTimedAmongThePasses) {
    Scene scene = default_scene();
    ASSERT_TRUE(scene.lighting.shadows);
    scene.camera.width = 64;
    scene.camera.height = 48;
    const auto names = [](const FrameStats& stats) {
        std::vector<std::string> out;
        for (const PassTime& p : stats.passes) out.push_back(p.name);
        return out;
    };
    const auto total = [](const FrameStats& stats) {
        double sum = 0.0;
        for (const PassTime& p : stats.passes) sum += p.ms;
        return sum;
    };
    PpllMethod ppll(device());
    FrameStats stats;
    for (const ShadowTechnique technique : {ShadowTechnique::Accurate, ShadowTechnique::PerSphere}) {
        scene.render.shadow_technique = technique;
        ppll.render(scene, &stats);
        const std::vector<std::string> passes = names(stats);
        ASSERT_GE(passes.size(), 4u);
        EXPECT_EQ(passes[0], "sort (cpu)");
        EXPECT_EQ(passes[1], "sun grid (cpu)");  // the ground is lit: the opaque pass reads the grid
        EXPECT_EQ(passes[2], technique == ShadowTechnique::Accurate ? "sun map (cpu)" : "sphere sun (cpu)");
        EXPECT_EQ(passes[3], "clear+opaque");
        EXPECT_GT(stats.passes[2].ms, 0.0);
        EXPECT_DOUBLE_EQ(stats.total_ms, total(stats));
    }
    scene.lighting.shadows = false;
    ppll.render(scene, &stats);
    const std::vector<std::string> passes = names(stats);
    for (const char* light : {"sun grid (cpu)", "sphere sun (cpu)", "sun map (cpu)"})
        EXPECT_EQ(std::count(passes.begin(), passes.end(), light), 0) << light;
    EXPECT_EQ(passes[1], "clear+opaque");
}

// Peel's early stop runs as frame steps: the frame path submits the next step when asked.
TEST_F(FramePathTest, StepsStopEarlyWhenNothingIsLeftToPeel) {
    Scene scene = small_scene(40, 30);
    scene.spheres.push_back(sphere({0.0, 0.0, 0.0}, 0.5, 1.0));  // one layer
    PeelOptions options;
    options.passes = 16;
    options.passes_per_submit = 2;
    PeelMethod peel(device(), options);
    peel.render(scene);
    EXPECT_LT(peel.last_frame().passes_recorded, 16);
    EXPECT_EQ(peel.last_frame().passes_drawn, 2);  // the layer, then a pass that found nothing
}

// What a window shows is what the PNG writer writes: the tone-map pass gives the same 8-bit codes
// (to one code: the GPU's float pow against the writer's double one) at several exposures.
TEST_F(FramePathTest, ToneMapMatchesThePngWriter) {
    Scene scene = default_scene();
    scene.camera.width = 64;
    scene.camera.height = 48;
    PpllMethod ppll(device());
    FramePath path(device());
    const Image hdr = path.render(ppll, scene);
    for (double stops : {-1.0, 0.0, 1.5}) {
        OffscreenPresenter screen(device(), {64, 48}, stops);
        ASSERT_TRUE(path.render_to(screen, ppll, scene));
        const std::vector<std::uint8_t>& px = screen.pixels();
        int worst = 0, exact = 0, nonzero = 0;
        for (int p = 0; p < 64 * 48; ++p)
            for (int c = 0; c < 3; ++c) {
                const int want = png_code(hdr.rgb[std::size_t(p) * 3 + c], std::exp2(stops));
                const int got = px[std::size_t(p) * 4 + c];
                worst = std::max(worst, std::abs(got - want));
                exact += got == want;
                nonzero += want > 0;
            }
        EXPECT_LE(worst, 1) << stops;
        EXPECT_GT(exact, 64 * 48 * 3 * 95 / 100) << stops;
        EXPECT_GT(nonzero, 64 * 48) << stops;  // the scene is not black: the comparison means something
        for (int p = 0; p < 64 * 48; ++p) EXPECT_EQ(px[std::size_t(p) * 4 + 3], 255);
    }
}

// NaN, infinity, negatives and overexposure land where the PNG writer puts them.
TEST_F(FramePathTest, ToneMapClampsLikeThePngWriter) {
    EXPECT_EQ(png_code(std::nanf(""), 1.0), 0);
    EXPECT_EQ(png_code(-1.0f, 1.0), 0);
    EXPECT_EQ(png_code(INFINITY, 1.0), 255);
    EXPECT_EQ(png_code(0.5f, 4.0), 255);
    EXPECT_EQ(png_code(0.21586f, 1.0), 128);  // sRGB 128/255 encodes 0.21586 linear
    EXPECT_EQ(png_code(0.21223f, 1.0), 127);  // and 127/255 encodes 0.21223
}

// `--device lavapipe`, the default the README and --help name, finds Mesa's driver, which calls
// itself llvmpipe; other names match as substrings, ignoring case.
TEST(DeviceNames, LavapipeMeansLlvmpipe) {
    EXPECT_TRUE(vk::device_name_matches("llvmpipe (LLVM 15.0.6, 256 bits)", "lavapipe"));
    EXPECT_TRUE(vk::device_name_matches("llvmpipe (LLVM 15.0.6, 256 bits)", "LavaPipe"));
    EXPECT_TRUE(vk::device_name_matches("llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe"));
    EXPECT_TRUE(vk::device_name_matches("NVIDIA H200", "h200"));
    EXPECT_FALSE(vk::device_name_matches("NVIDIA H200", "lavapipe"));
    EXPECT_FALSE(vk::device_name_matches("llvmpipe (LLVM 15.0.6, 256 bits)", "nvidia"));
}

// `--device` picks one device or says why not: by number ('#N', as `brume devices` lists them), by the
// one name it matches, the first of identical devices, never silently one of two different ones.
TEST(DeviceNames, OneDeviceIsPickedOrTheChoiceIsRefused) {
    const std::vector<std::string> names{"NVIDIA H100", "llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100", "NVIDIA A10"};
    EXPECT_EQ(vk::pick_device(names, ""), 1u);  // lavapipe by default
    EXPECT_EQ(vk::pick_device(names, "h100"), 0u);  // two of the same: the first...
    EXPECT_EQ(vk::pick_device(names, "#2"), 2u);    // ... and the other by its number
    EXPECT_EQ(vk::pick_device(names, "a10"), 3u);
    for (const char* wanted : {"nvidia", "#4", "#", "#x", "#-1", "amd"}) {
        try {
            (void)vk::pick_device(names, wanted);
            ADD_FAILURE() << wanted << " was accepted";
        } catch (const vk::VulkanError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("#3 'NVIDIA A10'"), std::string::npos) << what;  // the choices, numbered
            EXPECT_NE(what.find(wanted), std::string::npos) << what;
        }
    }
    EXPECT_EQ(vk::pick_device({"NVIDIA H200"}, ""), 0u);  // no lavapipe: what there is
    EXPECT_THROW((void)vk::pick_device({}, "h200"), vk::VulkanError);
}

// Positions reach the device relative to the eye (render/vk/gpu_types.h): the same shadowed scene over
// a lit ground, moved 100,000-300,000 units from the world's origin, renders by every GPU method as it
// does at the origin. In float world coordinates ppll's sphere edges there were off by 0.13 of the
// peak (float keeps 0.008 of a unit at 1e5).
TEST_F(FramePathTest, EveryMethodRendersAFarSceneAsItsCopyAtTheOrigin) {
    Scene near = testing::shadowed_cloud(false);
    near.camera.width = 48;
    near.camera.height = 36;
    Scene far = near;
    const glm::dvec3 away{1e5, -2e5, 3e5};
    far.camera.position += away;
    far.camera.look_at += away;
    for (Sphere& sp : far.spheres) sp.center += away;
    for (Box& b : far.boxes) {
        b.min += away;
        b.max += away;
    }
    for (const MethodEntry& entry : method_catalogue()) {
        if (!entry.needs_device) continue;
        const std::string& spec = entry.name;
        auto method = make_method(&device(), spec);
        const Image at_origin = method->render(near), away_from_it = method->render(far);
        const ImageDiff d = compare_images(away_from_it, at_origin, 1e-5);
        EXPECT_EQ(d.pixels_over, 0u) << spec << ": " << describe(d);
    }
}

TEST_F(FramePathTest, LavapipeByTheNameUsersType) {
    vk::DeviceOptions options;
    options.device_name = "lavapipe";
    vk::Device named(options);
    EXPECT_NE(named.name().find("llvmpipe"), std::string::npos);
}

}  // namespace
}  // namespace brume
