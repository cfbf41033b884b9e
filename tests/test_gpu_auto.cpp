// `auto`: on a GPU, power-distance sorting where no spheres intersect (exact there, but for accurate
// shadows); otherwise the fastest of tiles, ppll and trace (the float CPU tracer) as measured on this
// device, and the next one when a path refuses a frame. lavapipe is a CPU device, so auto takes trace
// here for every frame unless a test keeps it to the GPU paths (allow_cpu = false) or asks it to
// measure (then trace first, ppll, tiles).
#include "gpu_test_env.h"
#include "shadow_error.h"
#include "test_scenes.h"
#include "render/methods/auto_method.h"
#include "render/methods/ppll.h"
#include "render/methods/registry.h"
#include "sim/sphere_overlap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;
using testing::sphere;

Scene scene_with(std::vector<Sphere> spheres) {
    Scene s = testing::small_scene(96, 72);  // min_transmittance 0: the compositor integrates everything; see auto_method.h
    s.camera.position = {0, 0, 0};
    s.camera.look_at = {0, 0, -1};
    s.camera.fov_y_deg = 70;
    s.spheres = std::move(spheres);
    s.boxes.push_back(Box{{-40, -9, -60}, {40, -8, 0}, {0.25, 0.22, 0.2}});
    return s;
}

class Auto : public GpuTest {};

// As on a GPU: auto without trace.
AutoOptions gpu_paths() {
    AutoOptions o;
    o.allow_cpu = false;
    return o;
}

std::vector<Sphere> random_disjoint_spheres() {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Sphere> spheres;
    while (spheres.size() < 60) {
        Sphere s = sphere({u(rng) * 16 - 8, u(rng) * 12 - 6, -4 - u(rng) * 20}, 0.1 + u(rng) * (u(rng) < 0.1 ? 3.0 : 0.6),
                          0.2 + 3 * u(rng), {u(rng), u(rng), u(rng)});
        std::vector<Sphere> trial = spheres;
        trial.push_back(s);
        if (!find_intersecting_spheres(trial)) spheres = trial;
    }
    return spheres;
}

TEST_F(Auto, OnTheGpuPathsDisjointSpheresTakeTheSortedPathAndStayExact) {
    // Random disjoint spheres of very different sizes: the sorted path must be exact.
    const Scene s = scene_with(random_disjoint_spheres());
    AutoMethod method(device(), gpu_paths());
    const Image img = method.render(s, nullptr);
    EXPECT_EQ(method.last_choice(), "power-sorted");
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

// On a CPU device trace is faster than the compositor on disjoint spheres too (docs/methods.md, "auto").
TEST_F(Auto, OnACpuDeviceDisjointSpheresTakeTrace) {
    ASSERT_EQ(device().properties().deviceType, VK_PHYSICAL_DEVICE_TYPE_CPU) << "the tests run on lavapipe";
    const Scene s = scene_with(random_disjoint_spheres());
    AutoMethod method(device());
    FrameStats stats;
    const Image img = method.render(s, &stats);
    EXPECT_EQ(method.last_choice(), "trace");
    ASSERT_FALSE(stats.passes.empty());
    EXPECT_EQ(stats.passes.front().name, "decide (cpu): trace");  // the stats name the path taken
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

// The compositor lights each sphere by one sun transmittance, the per-sphere technique's: with
// accurate shadows a disjoint frame must take an exact path, or a sphere in another's shadow is lit
// wrongly across its face while the stats name the accurate technique. Per-sphere shadows may still
// take the compositor, which is exact for them.
TEST_F(Auto, AccurateShadowsOnDisjointSpheresDoNotTakeTheCompositor) {
    Scene s = testing::small_scene(96, 72);
    s.camera.position = {0, 1, 6};
    s.camera.look_at = {0, 1, 0};
    s.lighting.shadows = true;
    s.lighting.sun_direction = {0, -1, 0};
    s.boxes.push_back(Box{{-5, -1, -5}, {5, 0, 5}, {0.1, 0.1, 0.1}, {0.6, 0.6, 0.6}});  // a lit floor
    // The upper sphere's shadow covers part of the lower one.
    s.spheres = {sphere({0.3, 2.2, 0}, 0.7, 3.0, {0.9, 0.9, 0.9}), sphere({0, 0.8, 0}, 0.6, 3.0, {0.9, 0.9, 0.9})};
    ASSERT_FALSE(find_intersecting_spheres(s.spheres));
    ASSERT_EQ(s.render.shadow_technique, ShadowTechnique::Accurate);
    const Image exact = render_reference(s);
    for (const bool cpu : {true, false}) {
        AutoMethod method(device(), cpu ? AutoOptions{} : gpu_paths());
        const Image img = method.render(s, nullptr);
        EXPECT_EQ(method.last_choice(), cpu ? "trace" : "ppll");
        const testing::ShadowError e = testing::shadow_error(img, exact);
        EXPECT_LT(e.mean, 1e-3) << method.last_choice();
        EXPECT_LT(e.p999, 1e-2) << method.last_choice();
    }
    Scene per_sphere = s;
    per_sphere.render.shadow_technique = ShadowTechnique::PerSphere;
    AutoMethod method(device(), gpu_paths());
    const Image img = method.render(per_sphere, nullptr);
    EXPECT_EQ(method.last_choice(), "power-sorted");
    ReferenceOptions o;
    o.shadows = ReferenceShadows::PerSphere;
    const ImageDiff d = compare_with_reference(img, testing::ReferenceImage(per_sphere, o));
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

TEST_F(Auto, PowerDistanceFixesWhatCentreDepthGetsWrong) {
    // Found by a random search: a big sphere beside a small one, disjoint, where the small one's
    // centre is nearer but the big one is entered first along some rays.
    const Scene s = scene_with({sphere({-6.954, 2.015, -12.298}, 0.919, 3.0, {0.95, 0.2, 0.1}),
                                sphere({8.865, 5.527, -12.366}, 15.061, 0.08, {0.2, 0.4, 0.95})});
    AutoMethod method(device(), gpu_paths());
    const Image exact = method.render(s, nullptr);
    EXPECT_EQ(method.last_choice(), "power-sorted");
    const ImageDiff d = compare_with_reference(exact, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    // The same compositing with the painter's centre-depth key is visibly wrong here.
    auto soft = make_method(&device(), "soft");
    const ImageDiff wrong = compare_with_reference(soft->render(s, nullptr), s);
    EXPECT_GT(wrong.pixels_over, 10u) << describe(wrong);
}

TEST_F(Auto, IntersectingSpheresTakeTraceFirstOnACpuDeviceAndPpllWithoutIt) {
    const Scene s = scene_with({sphere({0, 0, -6}, 1.0, 2.0, {0.9, 0.3, 0.2}), sphere({0.6, 0.2, -6.3}, 0.9, 3.0, {0.2, 0.4, 0.9})});
    AutoMethod method(device());
    const Image img = method.render(s, nullptr);
    EXPECT_EQ(method.last_choice(), "trace");
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);

    AutoOptions gpu_only;
    gpu_only.allow_cpu = false;
    AutoMethod lists(device(), gpu_only);
    FrameStats stats;
    const Image by_lists = lists.render(s, &stats);
    EXPECT_EQ(lists.last_choice(), "ppll");
    EXPECT_GT(stats.fragments, 0u);
    const ImageDiff e = compare_with_reference(by_lists, s);
    EXPECT_EQ(e.pixels_over, 0u) << describe(e);
}

// On a CPU device an animation takes trace on every frame, measured or not: its images do not
// depend on the machine's load.
TEST_F(Auto, OnACpuDeviceEveryIntersectingFrameTakesTrace) {
    Scene s = testing::random_scene(48, 36, 60, 3, false);
    AutoMethod method(device());
    for (int frame = 0; frame < 6; ++frame) {
        s.camera.position.x = 0.3 + 0.05 * frame;
        method.render(s, nullptr);
        EXPECT_EQ(method.last_choice(), "trace") << "frame " << frame;
    }
    EXPECT_LT(method.measured_cost("ppll"), 0.0);
}

AutoOptions measuring() {
    AutoOptions o;
    o.measure_on_cpu = true;  // lavapipe is a CPU device: measure anyway, to test the measurements
    return o;
}

// Intersecting spheres over several frames of a moving camera: auto measures trace (after a warm-up
// frame), ppll and tiles, then takes the one it measured fastest; every frame is exact.
TEST_F(Auto, AnAnimationTakesTheFastestExactPathItMeasured) {
    Scene s = testing::random_scene(64, 48, 60, 3, false);
    AutoMethod method(device(), measuring());
    std::vector<std::string> taken, fastest_before;  // the path taken; the fastest measured before the frame
    for (int frame = 0; frame < 8; ++frame) {
        const double ppll = method.measured_cost("ppll"), trace = method.measured_cost("trace"),
                     tiles = method.measured_cost("tiles");
        if (frame >= 6) {
            // Every path measured by then (each measures the path it takes, so the figures move).
            EXPECT_GT(ppll, 0.0);
            EXPECT_GT(trace, 0.0);
            EXPECT_GT(tiles, 0.0);
        }
        const double fastest = std::min({ppll, trace, tiles});
        fastest_before.push_back(fastest == trace ? "trace" : fastest == ppll ? "ppll" : "tiles");
        s.camera.position.x = 0.3 + 0.05 * frame;  // a changed scene every frame
        FrameStats stats;
        const Image img = method.render(s, &stats);
        taken.push_back(method.last_choice());
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << "frame " << frame << " by " << taken.back() << ": " << describe(d);
        ASSERT_FALSE(stats.passes.empty());
        EXPECT_EQ(stats.passes.front().name, "decide (cpu): " + taken.back());
    }
    // Frame 0 is trace's warm-up (not a measurement), frame 1 measures it, frames 2 and 3 ppll (its
    // first frame compiles its pipelines), 4 and 5 tiles; then the fastest as measured so far.
    const std::vector<std::string> order = {"trace", "trace", "ppll", "ppll", "tiles", "tiles"};
    for (std::size_t f = 0; f < order.size(); ++f) EXPECT_EQ(taken[f], order[f]) << "frame " << f;
    for (std::size_t f = 6; f < taken.size(); ++f) EXPECT_EQ(taken[f], fastest_before[f]) << "frame " << f;
}

// A path not taken is measured again after kRemeasureEvery changed frames per time it was slower, so
// re-measuring costs about the same share of the time however slow the path is (a 20x slower trace on
// a GPU would otherwise stall a preview every 60 frames); a refused path waits the longest.
TEST(AutoRemeasure, TheSlowerAPathTheLaterItIsMeasuredAgain) {
    const int every = AutoMethod::kRemeasureEvery, most = every * AutoMethod::kMaxRemeasureFactor;
    EXPECT_EQ(AutoMethod::remeasure_interval(1.0, 1.0), every);
    EXPECT_EQ(AutoMethod::remeasure_interval(0.5, 1.0), every);  // faster: it was the best when measured
    EXPECT_EQ(AutoMethod::remeasure_interval(2.5, 1.0), 3 * every);
    EXPECT_EQ(AutoMethod::remeasure_interval(20.0, 1.0), 20 * every);
    EXPECT_EQ(AutoMethod::remeasure_interval(1e9, 1.0), most);
    EXPECT_EQ(AutoMethod::remeasure_interval(std::numeric_limits<double>::infinity(), 1.0), most);
    EXPECT_EQ(AutoMethod::remeasure_interval(1.0, std::numeric_limits<double>::infinity()), every);  // nothing to compare
}

// Over a long animation a frame takes the fastest path measured before it, except when another path's
// turn to be measured again has come: after the first six frames (each path's warm-up and
// measurement), at most one frame in kRemeasureEvery per other path. (On lavapipe trace and ppll are
// near each other on so small a scene, so the fastest may change from frame to frame.)
TEST_F(Auto, ALongAnimationMeasuresTheOtherPathsOnlyNowAndThen) {
    Scene s = testing::random_scene(48, 36, 40, 3, false);
    AutoMethod method(device(), measuring());
    constexpr int kChanged = 2 * AutoMethod::kRemeasureEvery;
    int remeasured = 0;
    std::string taken_by;
    for (int frame = 0; frame < 6 + kChanged; ++frame) {
        const double ppll = method.measured_cost("ppll"), trace = method.measured_cost("trace"),
                     tiles = method.measured_cost("tiles");
        const double fastest = std::min({ppll, trace, tiles});
        const std::string fastest_before = fastest == trace ? "trace" : fastest == ppll ? "ppll" : "tiles";
        s.camera.position.x = 0.3 + 0.002 * frame;
        method.render(s, nullptr);
        if (frame >= 6 && method.last_choice() != fastest_before) {
            ++remeasured;
            taken_by.append(" ").append(std::to_string(frame)).append(":").append(method.last_choice());
        }
    }
    EXPECT_LE(remeasured, 2 * (kChanged / AutoMethod::kRemeasureEvery)) << "frames on another path:" << taken_by;
}

// A path that refuses a frame (here a memory budget far below what the scene needs) is not an error
// when another path can render it: the same frame is rendered by the next one, exactly, and the path
// that refused counts as the slowest (it is measured again later, in turn).
TEST_F(Auto, APathThatRefusesAFrameHandsItToTheNext) {
    Scene s = testing::random_scene(64, 48, 60, 3, false);
    AutoOptions o = measuring();
    o.allow_cpu = false;  // ppll first, then tiles
    o.ppll.max_pool_bytes = 4096;  // a few hundred nodes: every frame overflows ppll's budget
    AutoMethod method(device(), o);
    for (int frame = 0; frame < 4; ++frame) {
        s.camera.position.x = 0.3 + 0.05 * frame;
        const Image img = method.render(s, nullptr);
        EXPECT_EQ(method.last_choice(), "tiles") << "frame " << frame;
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << "frame " << frame << ": " << describe(d);
    }
    EXPECT_TRUE(std::isinf(method.measured_cost("ppll")));
    EXPECT_GT(method.measured_cost("tiles"), 0.0);

    // The other way round: tiles refuses, ppll (measured on the frames before) renders the frame.
    AutoOptions t = measuring();
    t.allow_cpu = false;
    t.tiles.max_bytes = 4096;
    AutoMethod lists(device(), t);
    for (int frame = 0; frame < 4; ++frame) {
        s.camera.position.x = 0.3 + 0.05 * frame;
        const Image img = lists.render(s, nullptr);
        EXPECT_EQ(lists.last_choice(), "ppll") << "frame " << frame;
        EXPECT_EQ(compare_with_reference(img, s).pixels_over, 0u) << "frame " << frame;
    }
    EXPECT_TRUE(std::isinf(lists.measured_cost("tiles")));

    // With every path refusing, the frame is refused: the last path's own error, never an image.
    AutoOptions none = t;
    none.ppll.max_pool_bytes = 4096;
    AutoMethod neither(device(), none);
    EXPECT_THROW(neither.render(s, nullptr), std::runtime_error);
}

// The same scene twice takes the same path (so repeated renders stay identical), and with shadows
// both paths compute the same accurate technique: every frame of a shadowed animation agrees with
// ppll's to float precision, whichever path took it.
TEST_F(Auto, RepeatedFramesKeepTheirPathAndShadowedFramesMeetTheShadowTarget) {
    Scene s = testing::random_scene(48, 36, 40, 5, false);
    AutoMethod method(device(), measuring());
    for (int frame = 0; frame < 4; ++frame) {
        s.camera.position.x = 0.3 + 0.05 * frame;
        method.render(s, nullptr);
    }
    const std::string before = method.last_choice();
    const Image a = method.render(s, nullptr);
    const Image b = method.render(s, nullptr);
    EXPECT_EQ(method.last_choice(), before);
    EXPECT_EQ(a.rgb, b.rgb);

    Scene lit = s;
    lit.lighting.shadows = true;
    lit.boxes.push_back(Box{{-5, -1.5, -5}, {5, -1, 5}, {0.1, 0.1, 0.1}, {0.6, 0.6, 0.6}});  // a lit floor in shadow
    AutoMethod shadowed(device(), measuring());
    auto ppll = make_method(&device(), "ppll");
    std::vector<std::string> taken;
    for (int frame = 0; frame < 5; ++frame) {
        lit.camera.position.x = 0.3 + 0.05 * frame;
        const Image by_auto = shadowed.render(lit, nullptr);
        taken.push_back(shadowed.last_choice());
        const Image by_ppll = ppll->render(lit, nullptr);
        // Either path's accurate technique (trace's and ppll's read the same kind of light-space depth
        // map, and differ in how they sample it along a segment) within the target of the
        // exact model, and so near each other.
        const Image exact = render_reference(lit);
        for (const auto& [name, img] : {std::pair<const char*, const Image*>{"auto", &by_auto}, {"ppll", &by_ppll}}) {
            const testing::ShadowError e = testing::shadow_error(*img, exact);
            EXPECT_LT(e.mean, 1e-3) << name << " frame " << frame << " by " << taken.back();
            EXPECT_LT(e.p999, 1e-2) << name << " frame " << frame << " by " << taken.back();
        }
    }
    EXPECT_EQ(taken[0], "trace");
    EXPECT_EQ(taken[2], "ppll");
}

// Long lists (issue 14 item 1 names auto beside ppll): whichever path auto takes, a list of 800, 3,000
// or 20,000 nodes, thin or thick, is exact against the reference with its medium present, or the frame
// is refused; never a wrong image. On a CPU device auto takes trace, which has no loop limit, so every
// case must be exact here; on a GPU, ppll's general path may refuse coincident lists past 400 nodes.
using testing::LongList;

class AutoLongLists : public GpuTest, public ::testing::WithParamInterface<LongList> {};

TEST_P(AutoLongLists, AreExactOrRefusedNeverWrong) {
    const LongList p = GetParam();
    const Scene s = testing::long_list_scene(p);
    auto method = make_method(&device(), "auto");
    try {
        const Image img = method->render(s, nullptr);
        const ImageDiff d = compare_with_reference(img, s);
        if (p.coincident && p.nodes >= 20000) {
            // 20,000 media open at one point: their extinctions are summed in float, 20,000 additions whose
            // rounding reaches about n * 2^-24 = 1.2e-3 of the sum (measured: 2e-4 of the peak), beyond
            // the reference's one-ray conditioning bound; still far from a dropped medium (the whole peak).
            EXPECT_LE(d.max_excess, 1e-3) << describe(d);
        } else {
            EXPECT_EQ(d.pixels_over, 0u) << describe(d);
        }
        EXPECT_NE(img.pixel(7, 7)[0], img.pixel(0, 0)[0]) << "the list's medium is missing from the image";
    } catch (const ListResolveError& e) {
        EXPECT_TRUE(p.coincident && p.nodes > 400) << e.what();
        EXPECT_NE(device().properties().deviceType, VK_PHYSICAL_DEVICE_TYPE_CPU) << "on a CPU device auto takes trace, which must not refuse: " << e.what();
    }
}

// The GPU paths alone, as on a GPU without trace: ppll refuses the coincident lists past 400 nodes
// on lavapipe (its loop limit), and auto hands those frames to tiles within the same frame; what
// tiles cannot resolve either is refused. Exact or refused, never wrong.
TEST_P(AutoLongLists, OnTheGpuPathsAloneAreExactOrRefusedNeverWrong) {
    const LongList p = GetParam();
    const Scene s = testing::long_list_scene(p);
    AutoOptions o;
    o.allow_cpu = false;
    o.measure_on_cpu = true;
    AutoMethod method(device(), o);
    try {
        const Image img = method.render(s, nullptr);
        const ImageDiff d = compare_with_reference(img, s);
        if (p.coincident && p.nodes >= 20000)
            EXPECT_LE(d.max_excess, 1e-3) << describe(d);  // float sums of 20,000 extinctions (above)
        else
            EXPECT_EQ(d.pixels_over, 0u) << method.last_choice() << ": " << describe(d);
        EXPECT_NE(img.pixel(7, 7)[0], img.pixel(0, 0)[0]) << "the list's medium is missing from the image";
    } catch (const ListResolveError& e) {
        EXPECT_TRUE(p.coincident && p.nodes > 400) << e.what();
        // Refused only once both paths refused it within the frame.
        EXPECT_TRUE(std::isinf(method.measured_cost("ppll"))) << e.what();
        EXPECT_TRUE(std::isinf(method.measured_cost("tiles"))) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(Lengths, AutoLongLists,
                         ::testing::ValuesIn(testing::long_lists()),
                         [](const ::testing::TestParamInfo<LongList>& info) { return testing::long_list_name(info.param); });

}  // namespace
}  // namespace brume
