// Every method of the catalogue (render/methods/registry.h), at its default setting and at each setting
// `brume bench` sweeps, through the tests that hold for all of them: the factory names the method and
// refuses bad settings; where no medium is in front, the opaque radiance shows; images are finite and
// of the camera's size, across changes of size; FrameStats are filled; consecutive frames of one scene
// are identical; methods marked exact match the CPU reference, the others stay within a sanity bound.
// A method added to the catalogue is tested here without editing this file. What only one method
// promises (peel's early stop, kbuf's k nearest, stochastic's convergence, sorted's popping, ...) is
// tested in its own tests/test_gpu_*.cpp.
#include "gpu_test_env.h"
#include "test_scenes.h"

#include "render/methods/registry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;
using testing::ReferenceImage;
using testing::same_bits;
using testing::small_scene;
using testing::sphere;

// Every entry at its default setting, then at each of its bench settings: "kbuf", "kbuf:4", "kbuf:16".
// The reference too: it is a method like the others (the catalogue's entries: test_method_registry.cpp).
std::vector<std::string> catalogue_specs() {
    std::vector<std::string> specs;
    for (const MethodEntry& m : method_catalogue()) {
        specs.push_back(m.name);
        for (const std::string& s : m.bench_settings) specs.push_back(m.name + ":" + s);
    }
    return specs;
}

// The name a method gives itself: the spec with the default setting filled in ("kbuf" -> "kbuf:8").
std::string canonical_name(const std::string& spec) {
    const MethodEntry& entry = find_method(spec);
    if (entry.setting.empty()) return entry.name;
    const std::size_t colon = spec.find(':');
    return entry.name + ":" + (colon == std::string::npos ? entry.default_setting : spec.substr(colon + 1));
}

// Within 4 ulps, as EXPECT_FLOAT_EQ.
bool float_eq(float a, double b) { return ::testing::internal::FloatingPoint<float>(a).AlmostEquals(::testing::internal::FloatingPoint<float>(float(b))); }

// Pixels whose radiance is not `want` (to 4 ulps in every channel).
int pixels_not(const Image& img, const glm::dvec3& want) {
    int off = 0;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i)
            off += !(float_eq(img.pixel(i, j)[0], want[0]) && float_eq(img.pixel(i, j)[1], want[1]) &&
                     float_eq(img.pixel(i, j)[2], want[2]));
    return off;
}

class Methods : public GpuTest, public ::testing::WithParamInterface<std::string> {
protected:
    const MethodEntry& entry() const { return find_method(GetParam()); }
    std::unique_ptr<Method> make() { return make_method(&device(), GetParam()); }
};

TEST_P(Methods, FactoryNamesTheMethodAndRejectsBadSettings) {
    const MethodEntry& e = entry();
    const std::unique_ptr<Method> method = make();
    EXPECT_EQ(method->name(), canonical_name(GetParam()));
    // The name is a spec that makes the same method again.
    EXPECT_EQ(make_method(&device(), method->name())->name(), method->name());
    EXPECT_EQ(method->exact(), e.exact);
    EXPECT_EQ(method->gpu() != nullptr, e.needs_device);
    if (e.needs_device) {
        EXPECT_THROW(make_method(nullptr, GetParam()), std::invalid_argument);
    }
    if (e.setting.empty()) {
        for (const char* bad : {"4", "x"})
            EXPECT_THROW(make_method(&device(), e.name + ":" + bad), std::invalid_argument) << bad;
    } else {
        // Settings no syntax of the catalogue accepts: the factory itself refuses them too.
        for (const std::string& bad : {std::string("x"), std::string("0"), std::string("-1"), std::string("1000"),
                                       " " + e.default_setting, e.default_setting + "x"}) {
            EXPECT_THROW(make_method(&device(), e.name + ":" + bad), std::invalid_argument) << "'" << bad << "'";
            EXPECT_THROW(e.make(&device(), bad, {}), std::invalid_argument) << "'" << bad << "'";
        }
    }
}

TEST_P(Methods, OpaqueRadianceShowsWhereNoMediumIsInFront) {
    const std::unique_ptr<Method> method = make();
    // Nothing at all: the background everywhere.
    Scene s = small_scene(32, 24);
    FrameStats stats;
    Image img = method->render(s, &stats);
    ASSERT_EQ(img.width, 32);
    ASSERT_EQ(img.height, 24);
    EXPECT_EQ(pixels_not(img, s.lighting.background), 0);
    EXPECT_EQ(stats.fragments, 0u);
    // A box and no spheres: the box's radiance over it, the background around it, exactly the reference.
    s.boxes.push_back(Box{{-1, -1, -1}, {1, 1, 1}, {0.5, 0.25, 0.125}});
    img = method->render(s, &stats);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(img.pixel(16, 12)[c], float(s.boxes[0].radiance[c]));
        EXPECT_FLOAT_EQ(img.pixel(0, 0)[c], float(s.lighting.background[c]));
    }
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_EQ(stats.fragments, 0u);
    // The eye inside a box, a sphere behind it: the box's radiance hides the medium.
    Scene inside = small_scene(32, 32);
    inside.boxes.push_back(Box{{-1, -1, 4}, {1, 1, 6}, {0.25, 0.5, 0.75}});
    inside.spheres.push_back(sphere({0, 0, 0}, 1.0, 1.0));
    img = method->render(inside);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.pixel(16, 16)[c], float(inside.boxes[0].radiance[c]));
}

TEST_P(Methods, StatsAreFilled) {
    const MethodEntry& e = entry();
    const std::unique_ptr<Method> method = make();
    const Scene s = testing::overlapping_scene(48, 36);
    FrameStats stats;
    method->render(s, &stats);
    method->render(s, &stats);  // a second frame of the same scene reports as fully as the first
    ASSERT_FALSE(stats.passes.empty());
    double sum = 0.0;
    for (const PassTime& p : stats.passes) {
        EXPECT_FALSE(p.name.empty());
        EXPECT_TRUE(std::isfinite(p.ms) && p.ms >= 0.0) << p.name << " " << p.ms;
        sum += p.ms;
    }
    EXPECT_DOUBLE_EQ(stats.total_ms, sum);
    EXPECT_GT(stats.total_ms, 0.0);
    EXPECT_EQ(stats.regrows, 0);
    if (e.needs_device) {
        EXPECT_GT(stats.memory_bytes, 0u);
        // The frame path's shared pass is timed for every GPU method that reads it; the CPU tracers
        // (trace, and auto when it takes trace) meet the boxes themselves and time their trace instead.
        const bool opaque_pass = std::any_of(stats.passes.begin(), stats.passes.end(),
                                             [](const PassTime& p) { return p.name == "clear+opaque"; });
        const bool cpu_trace = std::any_of(stats.passes.begin(), stats.passes.end(),
                                           [](const PassTime& p) { return p.name == "trace (cpu)"; });
        EXPECT_NE(opaque_pass, cpu_trace) << "each frame has its opaque pass or its own trace, not both";
    }
    EXPECT_EQ(stats.list_stats, e.list_stats);
    if (e.list_stats) {
        EXPECT_GT(stats.fragments, 0u);
        EXPECT_GT(stats.nonempty_pixels, 0u);
        EXPECT_GT(stats.max_list_length, 0u);
        EXPECT_GT(stats.mean_list_length, 0.0);
    }
}

TEST_P(Methods, ConsecutiveFramesOfOneSceneAreIdentical) {
    // Tie-free random spheres: every catalogued method is deterministic on them (ppll's node order
    // depends on thread timing, but the resolve sorts by distance, and no two distances are equal).
    const Scene a = testing::random_scene(64, 48, 40, 5, true);
    const Scene b = testing::stacked_scene(48, 36);
    const std::unique_ptr<Method> method = make();
    const Image first = method->render(a);
    EXPECT_TRUE(same_bits(method->render(a), first)) << "second frame";
    method->render(b);  // another scene, at another size, in between
    EXPECT_TRUE(same_bits(method->render(a), first)) << "after another scene";
    EXPECT_TRUE(same_bits(make()->render(a), first)) << "a new instance";
}

// Scenes where the light model is hard to get exactly right: the single sphere has a closed form
// through its centre; the others are checked against the reference.
struct HardScene {
    const char* label;
    Scene scene;
    // With shadows these scenes ask for the per-sphere technique, which the reference computes in its
    // per-sphere mode: the reference method takes that mode itself (ReferenceMethod) from the scene.
    ReferenceOptions reference{};
};

std::vector<HardScene> hard_scenes() {
    std::vector<HardScene> out;
    {
        Scene s = small_scene(65, 65);  // odd: the centre pixel's ray goes exactly through the sphere centre
        s.spheres.push_back(sphere({0, 0, 0}, 1.0, 0.7));
        out.push_back({"single sphere", s});
    }
    {
        Scene s = small_scene(128, 96);
        s.boxes.push_back(Box{{-3, -3, -0.2}, {3, -0.3, 0.2}, {0.6, 0.2, 0.1}});  // slices through sphere 0
        s.boxes.push_back(Box{{0.2, -2, -2}, {0.5, 2, 2}, {0.1, 0.4, 0.2}});      // a wall through sphere 1
        s.spheres.push_back(sphere({-0.5, 0, 0}, 1.0, 1.2));
        s.spheres.push_back(sphere({0.6, 0.3, 0.5}, 0.9, 2.5, {0.2, 0.9, 0.4}));
        out.push_back({"spheres cut by boxes", s});
    }
    {
        Scene s = small_scene(128, 96);
        s.camera.position = {0.1, 0.0, 0.2};
        s.spheres.push_back(sphere({0, 0, 0}, 1.5, 0.4, {0.9, 0.9, 0.9}));
        s.spheres.push_back(sphere({0.3, 0.2, 0.1}, 0.8, 1.0, {0.3, 0.6, 0.9}));
        s.spheres.push_back(sphere({0, 0, -2}, 1.8, 0.5, {0.9, 0.5, 0.2}));  // contains the eye too
        s.spheres.push_back(sphere({0, 0, -3}, 0.5, 2.0));                   // in front, outside
        out.push_back({"eye inside several spheres", s});
    }
    {
        // Spheres whose front surface lies behind the eye (and so behind any near plane) but whose
        // volume reaches in front: they must be integrated from the eye, not dropped.
        Scene s = small_scene(128, 96);
        s.camera.position = {0, 0, 0};
        s.camera.look_at = {0, 0, -1};
        s.spheres.push_back(sphere({0.5, 0.0, 0.3}, 0.6, 2.0));    // contains the eye, centre behind it
        s.spheres.push_back(sphere({-0.8, 0.2, 0.4}, 0.7, 1.0));   // cut by the eye plane, eye outside
        s.spheres.push_back(sphere({0.0, -0.5, 0.01}, 0.2, 5.0));  // grazes the eye plane
        out.push_back({"spheres crossing the eye plane", s});
    }
    {
        Scene s = small_scene(128, 96);
        s.spheres.push_back(sphere({-0.5, 0, 0}, 0.5, 2.0, {0.9, 0.1, 0.1}));
        s.spheres.push_back(sphere({0.5, 0, 0}, 0.5, 2.0, {0.1, 0.9, 0.1}));  // tangent to the first
        s.spheres.push_back(sphere({0.5, 0, 0}, 0.5, 1.0, {0.1, 0.1, 0.9}));  // coincident with the second
        s.spheres.push_back(sphere({0.0, 1.0, 0}, 0.5, 1.0));                 // tangent to both from above
        out.push_back({"tangent and coincident spheres", s});
    }
    {
        // The light extension without shadows (docs/accuracy.md): emission, overlapping emitters, a lit
        // ground seen through them, a lit box seen from several faces; ppll stays exact.
        Scene s = small_scene(96, 72);
        s.camera.position = {1.5, 2.0, 5.0};
        Box ground{{-4, -1.5, -4}, {4, -1, 4}, {0.02, 0.02, 0.02}};
        ground.diffuse = {0.6, 0.5, 0.4};
        Box block{{0.8, -1, -0.5}, {1.6, 0.2, 0.3}, {0.0, 0.05, 0.0}};
        block.diffuse = {0.3, 0.4, 0.9};
        s.boxes = {ground, block};
        Sphere fire = sphere({-0.3, 0, 0}, 0.8, 1.5, {0.2, 0.1, 0.05});
        fire.emission = {2.0, 0.9, 0.2};
        Sphere smoke = sphere({0.3, 0.4, 0.2}, 0.7, 0.8, {0.5, 0.5, 0.5});
        Sphere glow = sphere({0.0, 0.2, 0.1}, 0.4, 3.0, {0.0, 0.0, 0.0});
        glow.emission = {4.0, 3.5, 2.0};  // inside both
        s.spheres = {fire, smoke, glow};
        out.push_back({"emission and lit boxes", s});
    }
    {
        // Dense puffs inside a thin atmosphere: leaving a puff must give the atmosphere back exactly.
        // Float running sums kept half a float step of the puff's extinction (1.2e-7, against the
        // atmosphere's 1e-6) for the rest of the ray, and every exact method read 4e-2 of the peak behind
        // it (render/compensated_sum.h).
        Scene s = small_scene(64, 48);
        s.camera.position = {0.0, 0.6, 3.0};
        s.camera.look_at = {0.0, 0.6, 0.0};
        s.camera.fov_y_deg = 20.0;
        s.spheres.push_back(sphere({0, 0, 0}, 1e6, 1e-6, {0.8, 0.8, 0.8}));
        s.spheres.push_back(sphere({0, 0.6, 0}, 0.3, 3.0, {0.9, 0.9, 0.95}));
        s.spheres.push_back(sphere({0.2, 0.5, -0.3}, 0.2, 8.0, {0.4, 0.6, 0.9}));
        s.spheres.back().emission = {0.5, 0.2, 0.1};
        out.push_back({"puffs inside a thin atmosphere", s});
    }
    {
        Scene s = small_scene(40, 30);
        s.camera.supersample = 3;  // the mean of 3 x 3 sub-pixel rays per pixel
        testing::add_back_wall(s);
        s.spheres.push_back(sphere({-0.4, 0, 0}, 0.9, 2.0, {0.9, 0.2, 0.2}));
        s.spheres.push_back(sphere({0.5, 0.3, 0.4}, 0.6, 4.0, {0.2, 0.9, 0.3}));
        s.spheres.back().emission = {0.5, 0.5, 1.5};
        out.push_back({"supersampled 3x3", s});
    }
    {
        // Shadows, per-sphere technique: the media's sun term is each sphere's T_sun at its centre, the lit
        // boxes' the exact T_sun at the hit, behind the smoke and a box. The eye is inside one sphere.
        Scene s = small_scene(80, 60);
        s.camera.position = {0.2, 0.3, 1.2};
        s.lighting.shadows = true;
        s.render.shadow_technique = ShadowTechnique::PerSphere;
        s.lighting.sun_direction = {-0.5, -1.0, -0.2};
        Box ground{{-6, -1.5, -6}, {6, -1, 6}, {0.0, 0.0, 0.0}};
        ground.diffuse = {0.7, 0.7, 0.7};
        Box post{{0.9, -1, -1.0}, {1.2, 1.5, -0.7}, {0.05, 0.0, 0.0}};
        post.diffuse = {0.5, 0.3, 0.2};
        s.boxes = {ground, post};
        s.spheres.push_back(sphere({0, 0.5, 0}, 0.7, 2.0, {0.9, 0.9, 0.9}));
        s.spheres.push_back(sphere({-0.6, 0.0, -0.4}, 0.6, 1.0, {0.8, 0.7, 0.6}));
        s.spheres.push_back(sphere({0.2, 0.3, 1.2}, 0.5, 0.6, {0.6, 0.7, 0.9}));  // holds the eye
        s.spheres.push_back(sphere({0.4, -0.6, -0.3}, 0.4, 3.0, {0.9, 0.5, 0.3}));
        HardScene h{"shadows, per-sphere", s};
        h.reference.shadows = ReferenceShadows::PerSphere;
        out.push_back(h);
    }
    return out;
}

// Methods not marked exact are held to sanity bounds on the scenes above, enough to catch an image
// that is blown out, garbage or missing the media: RMSE and largest error over the reference's peak
// (measured at most 0.58, wsum with the eye inside several spheres, and 1.71, screendoor:2 on the
// spheres crossing the eye plane), and, over all the scenes, how far the image moves away from the
// scene without spheres as a fraction of how far the reference moves (measured at least 0.98, wavg;
// sorted, which drops the spheres whose centres are behind the eye, shows nothing on that scene alone).
constexpr double kSanityRmse = 1.0;
constexpr double kSanityMax = 3.0;
constexpr double kSanitySeen = 0.25;

double mean_abs_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t k = 0; k < a.rgb.size(); ++k) sum += std::abs(double(a.rgb[k]) - b.rgb[k]);
    return sum / double(a.rgb.size());
}

TEST_P(Methods, ExactMethodsMatchTheReferenceOthersStayNearIt) {
    const MethodEntry& e = entry();
    const std::unique_ptr<Method> method = make();  // one instance for every scene: sizes change between frames
    double seen = 0.0, truth = 0.0;
    for (const HardScene& hs : hard_scenes()) {
        const Scene& s = hs.scene;
        const Image img = method->render(s);
        ASSERT_EQ(img.width, s.camera.width) << hs.label;
        ASSERT_EQ(img.height, s.camera.height) << hs.label;
        ASSERT_EQ(img.rgb.size(), std::size_t(s.camera.width) * s.camera.height * 3) << hs.label;
        EXPECT_TRUE(testing::all_finite(img)) << hs.label;
        const ReferenceImage ref(s, hs.reference);
        const ImageDiff d = compare_with_reference(img, ref);
        if (e.exact) {
            EXPECT_EQ(d.pixels_over, 0u) << hs.label << ": " << describe(d);
            if (s.spheres.size() == 1) {
                const glm::dvec3 centre = testing::single_sphere_radiance(s, 32, 32);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.pixel(32, 32)[c], centre[c], 1e-6) << hs.label << " channel " << c;
                // A corner pixel misses the sphere and shows the background.
                for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.pixel(0, 0)[c], float(s.lighting.background[c]));
            }
        } else {
            EXPECT_LT(d.rmse / d.peak, kSanityRmse) << hs.label << ": " << describe(d);
            EXPECT_LT(d.max_abs / d.peak, kSanityMax) << hs.label << ": " << describe(d);
        }
        Scene bare = s;
        bare.spheres.clear();
        const Image opaque = render_reference(bare, hs.reference);
        seen += mean_abs_difference(img, opaque);
        truth += mean_abs_difference(ref.image, opaque);
        std::printf("  %-20s %-32s rmse/peak %.3g  max/peak %.3g\n", GetParam().c_str(), hs.label, d.rmse / d.peak,
                    d.max_abs / d.peak);
    }
    std::printf("  %-20s media seen: %.3g of the reference's\n", GetParam().c_str(), seen / truth);
    EXPECT_GT(seen, kSanitySeen * truth) << "the media barely show";
}

INSTANTIATE_TEST_SUITE_P(Catalogue, Methods, ::testing::ValuesIn(catalogue_specs()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace
}  // namespace brume
