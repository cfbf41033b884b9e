// Scene files: the schema is read exactly, written back exactly, and every bad input is rejected with
// the file, line and key path (the contracts in README.md, "Tour").
#include "sim/builtin_scenes.h"
#include "sim/scene_file.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <unistd.h>

namespace brume {
namespace {

namespace fs = std::filesystem;

// The example from the schema, verbatim.
constexpr const char* kExample = R"(
[camera]
position = [0.0, 1.0, 6.0]
look_at = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 40.0            # vertical field of view
width = 160
height = 120
[lighting]
ambient = [0.25, 0.27, 0.30]        # L_ambient
sun = [1.0, 0.95, 0.85]             # L_sun, Rayleigh phase
sun_direction = [-0.4, -1.0, -0.3]  # direction the sunlight travels
background = [0.05, 0.06, 0.08]     # radiance where a ray meets no opaque surface
[render]
min_transmittance = 1e-4            # optional; stop integrating below this transmittance
[[box]]                             # opaque, axis aligned, flat radiance toward the eye
min = [-5.0, -1.0, -5.0]
max = [5.0, 0.0, 5.0]
radiance = [0.2, 0.2, 0.2]
[[sphere]]                          # one particle: homogeneous medium
center = [0.0, 0.6, 0.0]
radius = 0.8
extinction = 2.5                    # tau, per scene unit
albedo = [0.9, 0.9, 0.95]
)";

// Every key set to something other than its default, so a key the parser ignored would show.
constexpr const char* kEveryKey = R"(
[camera]
position = [1.5, 2.25, -7.0]
look_at = [0.125, -0.5, 3.0]
up = [0.1, 0.9, 0.2]
fov_y_deg = 65.5
width = 321
height = 99
[lighting]
ambient = [0.1, 0.2, 0.3]
sun = [4.0, 5.0, 6.0]
sun_direction = [1, -2, 3]
background = [0.7, 0.8, 0.9]
[render]
min_transmittance = 0
[[box]]
min = [-1, -2, -3]
max = [1, 2, 3]
radiance = [0.0, 0.5, 1.0]
[[box]]
min = [10, 10, 10]
max = [10.5, 11, 12]
radiance = [3, 2, 1]
[[sphere]]
center = [0.1, 0.2, 0.3]
radius = 1
extinction = 0
albedo = [0, 1, 0.5]
[[sphere]]
center = [-4, -5, -6]
radius = 2.5e-3
extinction = 1e9
albedo = [1, 1, 1]
)";

void expect_vec(const glm::dvec3& v, double x, double y, double z) {
    EXPECT_EQ(v.x, x);
    EXPECT_EQ(v.y, y);
    EXPECT_EQ(v.z, z);
}

// Bitwise, so -0.0 and 0.0 count as different and any printing loss shows.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const glm::dvec3& a, const glm::dvec3& b) {
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

void expect_identical(const Scene& a, const Scene& b) {
    EXPECT_TRUE(same_bits(a.camera.position, b.camera.position));
    EXPECT_TRUE(same_bits(a.camera.look_at, b.camera.look_at));
    EXPECT_TRUE(same_bits(a.camera.up, b.camera.up));
    EXPECT_TRUE(same_bits(a.camera.fov_y_deg, b.camera.fov_y_deg));
    EXPECT_EQ(a.camera.width, b.camera.width);
    EXPECT_EQ(a.camera.height, b.camera.height);
    EXPECT_EQ(a.camera.supersample, b.camera.supersample);
    EXPECT_EQ(a.lighting.shadows, b.lighting.shadows);
    EXPECT_TRUE(same_bits(a.lighting.ambient, b.lighting.ambient));
    EXPECT_TRUE(same_bits(a.lighting.sun, b.lighting.sun));
    EXPECT_TRUE(same_bits(a.lighting.sun_direction, b.lighting.sun_direction));
    EXPECT_TRUE(same_bits(a.lighting.background, b.lighting.background));
    EXPECT_TRUE(same_bits(a.render.min_transmittance, b.render.min_transmittance));
    EXPECT_EQ(a.render.shadow_technique, b.render.shadow_technique);
    ASSERT_EQ(a.boxes.size(), b.boxes.size());
    for (std::size_t i = 0; i < a.boxes.size(); ++i) {
        EXPECT_TRUE(same_bits(a.boxes[i].min, b.boxes[i].min)) << "box " << i;
        EXPECT_TRUE(same_bits(a.boxes[i].max, b.boxes[i].max)) << "box " << i;
        EXPECT_TRUE(same_bits(a.boxes[i].radiance, b.boxes[i].radiance)) << "box " << i;
        EXPECT_TRUE(same_bits(a.boxes[i].diffuse, b.boxes[i].diffuse)) << "box " << i;
    }
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (std::size_t i = 0; i < a.spheres.size(); ++i) {
        EXPECT_TRUE(same_bits(a.spheres[i].center, b.spheres[i].center)) << "sphere " << i;
        EXPECT_TRUE(same_bits(a.spheres[i].radius, b.spheres[i].radius)) << "sphere " << i;
        EXPECT_TRUE(same_bits(a.spheres[i].extinction, b.spheres[i].extinction)) << "sphere " << i;
        EXPECT_TRUE(same_bits(a.spheres[i].albedo, b.spheres[i].albedo)) << "sphere " << i;
        EXPECT_TRUE(same_bits(a.spheres[i].emission, b.spheres[i].emission)) << "sphere " << i;
    }
    // base_dir is where a file was read from, not part of what it says: not compared.
    ASSERT_EQ(a.volumes.size(), b.volumes.size());
    for (std::size_t i = 0; i < a.volumes.size(); ++i) {
        const VdbVolume &v = a.volumes[i], &w = b.volumes[i];
        EXPECT_EQ(v.source.file, w.source.file) << "volume " << i;
        EXPECT_EQ(v.source.grid, w.source.grid) << "volume " << i;
        EXPECT_EQ(v.albedo_grid, w.albedo_grid) << "volume " << i;
        EXPECT_TRUE(same_bits(v.extinction_scale, w.extinction_scale)) << "volume " << i;
        EXPECT_TRUE(same_bits(v.albedo, w.albedo)) << "volume " << i;
        EXPECT_EQ(v.max_spheres, w.max_spheres) << "volume " << i;
        // With a sphere budget the tolerance is unused, and not written.
        if (v.max_spheres == 0) {
            EXPECT_TRUE(same_bits(v.tolerance, w.tolerance)) << "volume " << i;
        }
        EXPECT_TRUE(same_bits(v.transform.translate, w.transform.translate)) << "volume " << i;
        EXPECT_TRUE(same_bits(v.transform.scale, w.transform.scale)) << "volume " << i;
        EXPECT_TRUE(same_bits(v.transform.rotate_deg, w.transform.rotate_deg)) << "volume " << i;
    }
}

TEST(SceneFile, ExampleParsesToExactValues) {
    const Scene s = parse_scene_toml(kExample, "example.toml");
    expect_vec(s.camera.position, 0.0, 1.0, 6.0);
    expect_vec(s.camera.look_at, 0.0, 0.5, 0.0);
    expect_vec(s.camera.up, 0.0, 1.0, 0.0);
    EXPECT_EQ(s.camera.fov_y_deg, 40.0);
    EXPECT_EQ(s.camera.width, 160);
    EXPECT_EQ(s.camera.height, 120);
    expect_vec(s.lighting.ambient, 0.25, 0.27, 0.30);
    expect_vec(s.lighting.sun, 1.0, 0.95, 0.85);
    expect_vec(s.lighting.sun_direction, -0.4, -1.0, -0.3);
    expect_vec(s.lighting.background, 0.05, 0.06, 0.08);
    EXPECT_EQ(s.render.min_transmittance, 1e-4);
    ASSERT_EQ(s.boxes.size(), 1u);
    expect_vec(s.boxes[0].min, -5.0, -1.0, -5.0);
    expect_vec(s.boxes[0].max, 5.0, 0.0, 5.0);
    expect_vec(s.boxes[0].radiance, 0.2, 0.2, 0.2);
    ASSERT_EQ(s.spheres.size(), 1u);
    expect_vec(s.spheres[0].center, 0.0, 0.6, 0.0);
    EXPECT_EQ(s.spheres[0].radius, 0.8);
    EXPECT_EQ(s.spheres[0].extinction, 2.5);
    expect_vec(s.spheres[0].albedo, 0.9, 0.9, 0.95);
    EXPECT_EQ(s.source, "example.toml");
}

TEST(SceneFile, EveryKeyIsRead) {
    const Scene s = parse_scene_toml(kEveryKey, "every.toml");
    expect_vec(s.camera.position, 1.5, 2.25, -7.0);
    expect_vec(s.camera.look_at, 0.125, -0.5, 3.0);
    expect_vec(s.camera.up, 0.1, 0.9, 0.2);
    EXPECT_EQ(s.camera.fov_y_deg, 65.5);
    EXPECT_EQ(s.camera.width, 321);
    EXPECT_EQ(s.camera.height, 99);
    expect_vec(s.lighting.ambient, 0.1, 0.2, 0.3);
    expect_vec(s.lighting.sun, 4.0, 5.0, 6.0);
    expect_vec(s.lighting.sun_direction, 1.0, -2.0, 3.0);  // integers read as floats
    expect_vec(s.lighting.background, 0.7, 0.8, 0.9);
    EXPECT_EQ(s.render.min_transmittance, 0.0);
    ASSERT_EQ(s.boxes.size(), 2u);
    expect_vec(s.boxes[1].min, 10.0, 10.0, 10.0);
    expect_vec(s.boxes[1].max, 10.5, 11.0, 12.0);
    expect_vec(s.boxes[1].radiance, 3.0, 2.0, 1.0);
    ASSERT_EQ(s.spheres.size(), 2u);  // file order is kept
    expect_vec(s.spheres[0].center, 0.1, 0.2, 0.3);
    EXPECT_EQ(s.spheres[0].radius, 1.0);
    EXPECT_EQ(s.spheres[0].extinction, 0.0);
    expect_vec(s.spheres[0].albedo, 0.0, 1.0, 0.5);
    expect_vec(s.spheres[1].center, -4.0, -5.0, -6.0);
    EXPECT_EQ(s.spheres[1].radius, 2.5e-3);
    EXPECT_EQ(s.spheres[1].extinction, 1e9);
}

TEST(SceneFile, DefaultsApplyToAbsentTablesAndKeys) {
    const Scene defaults;
    const Scene empty = parse_scene_toml("", "empty.toml");
    expect_identical(empty, defaults);
    EXPECT_TRUE(empty.boxes.empty());
    EXPECT_TRUE(empty.spheres.empty());
    EXPECT_EQ(empty.source, "empty.toml");

    const Scene partial = parse_scene_toml("[camera]\nwidth = 64\n[lighting]\nsun = [2, 2, 2]\n", "p.toml");
    EXPECT_EQ(partial.camera.width, 64);
    EXPECT_EQ(partial.camera.height, defaults.camera.height);
    EXPECT_TRUE(same_bits(partial.camera.position, defaults.camera.position));
    EXPECT_EQ(partial.camera.fov_y_deg, defaults.camera.fov_y_deg);
    expect_vec(partial.lighting.sun, 2.0, 2.0, 2.0);
    EXPECT_TRUE(same_bits(partial.lighting.ambient, defaults.lighting.ambient));
    EXPECT_TRUE(same_bits(partial.lighting.sun_direction, defaults.lighting.sun_direction));
    EXPECT_EQ(partial.render.min_transmittance, defaults.render.min_transmittance);
}

TEST(SceneFile, RoundTripIsExact) {
    const Scene original = parse_scene_toml(kEveryKey, "every.toml");
    const std::string text = scene_to_toml(original);
    expect_identical(parse_scene_toml(text, "written.toml"), original);
    // Floats stay floats in the written file, integers stay integers.
    EXPECT_NE(text.find("radius = 1.0\n"), std::string::npos) << text;
    EXPECT_NE(text.find("width = 321\n"), std::string::npos) << text;
}

TEST(SceneFile, RoundTripKeepsEveryBitOfAwkwardValues) {
    Scene s;
    s.camera.position = {0.1, 1.0 / 3.0, -2.0 / 7.0};
    s.camera.look_at = {-0.0, 5e-324, 1e-300};  // negative zero and the smallest subnormal survive
    s.camera.fov_y_deg = 179.0;
    s.camera.width = 16384;
    s.camera.height = 1;
    s.lighting.sun = {123456.789, 1e9, 0.30000000000000004};
    s.render.min_transmittance = 0.9999999999999999;
    s.boxes.push_back({{-1e7, -0.1, 3.0}, {1e7, 0.2, 3.0000000000000004}, {0.0, 0.0, 0.0}});
    for (int i = 0; i < 50; ++i) {
        const double x = std::sqrt(double(i) + 0.5);
        s.spheres.push_back({{x, -x / 3.0, std::exp(x)}, x / 7.0, std::pow(x, 5.0), {1.0 / (i + 1), 0.0, 1.0}});
    }
    const Scene back = parse_scene_toml(scene_to_toml(s), "awkward.toml");
    expect_identical(back, s);
    EXPECT_EQ(back.source, "awkward.toml");
}

// --- [[vdb]] volumes --------------------------------------------------------------------------------

// Every [[vdb]] key in the first table, the defaults in the second (but for max_spheres).
constexpr const char* kVolumes = R"(
[[vdb]]
file = "clouds/cumulus.vdb"
grid = "smoke"
albedo_grid = "tint"
extinction_scale = 2.5
albedo = [0.9, 0.8, 0.7]
tolerance = 0.02
translate = [1.0, -2.0, 0.5]
scale = 0.25
rotate = [10, 20, -30]

[[vdb]]
file = "builtin:cloud:32"
albedo = 0.75
max_spheres = 2000
)";

TEST(SceneFile, VdbTablesAreRead) {
    const Scene s = parse_scene_toml(kVolumes, "clouds.toml");
    ASSERT_EQ(s.volumes.size(), 2u);
    const VdbVolume& v = s.volumes[0];
    EXPECT_EQ(v.source.file, "clouds/cumulus.vdb");
    EXPECT_EQ(v.source.grid, "smoke");
    EXPECT_EQ(v.source.base_dir, "") << "parsing text reads no file: the working directory";
    EXPECT_EQ(v.albedo_grid, "tint");
    EXPECT_EQ(v.extinction_scale, 2.5);
    expect_vec(v.albedo, 0.9, 0.8, 0.7);
    EXPECT_EQ(v.tolerance, 0.02);
    EXPECT_EQ(v.max_spheres, 0u);
    expect_vec(v.transform.translate, 1.0, -2.0, 0.5);
    EXPECT_EQ(v.transform.scale, 0.25);
    expect_vec(v.transform.rotate_deg, 10.0, 20.0, -30.0);

    const VdbVolume defaults;
    const VdbVolume& w = s.volumes[1];
    EXPECT_EQ(w.source.file, "builtin:cloud:32");
    EXPECT_EQ(w.source.grid, "density");
    EXPECT_FALSE(w.albedo_grid.has_value()) << "unset: the file's \"albedo\" grid when it has one";
    EXPECT_EQ(w.extinction_scale, defaults.extinction_scale);
    expect_vec(w.albedo, 0.75, 0.75, 0.75);  // one number: grey
    EXPECT_EQ(w.max_spheres, 2000u);
    EXPECT_EQ(w.tolerance, defaults.tolerance);
    EXPECT_TRUE(same_bits(w.transform.translate, defaults.transform.translate));
    EXPECT_EQ(w.transform.scale, 1.0);
    EXPECT_TRUE(same_bits(w.transform.rotate_deg, defaults.transform.rotate_deg));
    EXPECT_TRUE(s.spheres.empty()) << "volumes are converted later, by sim/vdb/volume_loader.h";
}

TEST(SceneFile, VdbRoundTripIsExact) {
    const Scene original = parse_scene_toml(kVolumes, "clouds.toml");
    const std::string text = scene_to_toml(original);
    expect_identical(parse_scene_toml(text, "written.toml"), original);
    // Exactly one of tolerance and max_spheres per table, integers as integers.
    EXPECT_NE(text.find("tolerance = 0.02\n"), std::string::npos) << text;
    EXPECT_NE(text.find("max_spheres = 2000\n"), std::string::npos) << text;
    EXPECT_EQ(text.find("tolerance", text.find("max_spheres")), std::string::npos) << text;
    EXPECT_EQ(text.find("albedo_grid"), text.rfind("albedo_grid")) << "an unset albedo_grid is left out";
    // "" (no albedo grid, not even the file's "albedo") is kept apart from unset through a round trip.
    const Scene none = parse_scene_toml("[[vdb]]\nfile = \"c.vdb\"\nalbedo_grid = \"\"\n", "none.toml");
    ASSERT_TRUE(none.volumes[0].albedo_grid.has_value());
    EXPECT_EQ(*none.volumes[0].albedo_grid, "");
    const Scene none_again = parse_scene_toml(scene_to_toml(none), "again.toml");
    ASSERT_TRUE(none_again.volumes[0].albedo_grid.has_value());
    EXPECT_EQ(*none_again.volumes[0].albedo_grid, "");

    Scene s;
    VdbVolume v;
    v.source.file = "odd \"name\" \\ back\\slashed.vdb";  // escaped when written, read back as it was
    v.source.grid = "density";
    v.source.base_dir = "/not/written";
    v.extinction_scale = 1.0 / 3.0;
    v.albedo = {0.0, 0.30000000000000004, 1.0};
    v.tolerance = 5e-324;
    v.transform.translate = {-0.0, 1e7, -1.0 / 7.0};
    v.transform.scale = 1e-300;
    v.transform.rotate_deg = {3600.0, -0.1, 1e-10};
    s.volumes.push_back(v);
    v.max_spheres = 50'000'000;
    s.volumes.push_back(v);
    const std::string written = scene_to_toml(s);
    EXPECT_EQ(written.find("/not/written"), std::string::npos) << written;
    const Scene back = parse_scene_toml(written, "awkward.toml");
    expect_identical(back, s);
    EXPECT_EQ(back.volumes[0].source.base_dir, "");
}

TEST(SceneFile, DefaultSceneHasItsStatedContent) {
    const Scene s = default_scene();
    EXPECT_EQ(s.source, "built-in default scene");
    EXPECT_EQ(s.camera.width, 320);
    EXPECT_EQ(s.camera.height, 240);
    // A ground box whose top is y = 0 and that spans the view, then one or two more boxes.
    ASSERT_GE(s.boxes.size(), 2u);
    ASSERT_LE(s.boxes.size(), 3u);
    EXPECT_EQ(s.boxes[0].max.y, 0.0);
    EXPECT_LE(s.boxes[0].min.x, -10.0);
    EXPECT_GE(s.boxes[0].max.x, 10.0);
    // A plume of 40-80 spheres, varied in radius, extinction and albedo, each overlapping another.
    ASSERT_GE(s.spheres.size(), 40u);
    ASSERT_LE(s.spheres.size(), 80u);
    double min_r = 1e30, max_r = 0, min_tau = 1e30, max_tau = 0, min_a = 1, max_a = 0;
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
        const Sphere& a = s.spheres[i];
        min_r = std::min(min_r, a.radius);
        max_r = std::max(max_r, a.radius);
        min_tau = std::min(min_tau, a.extinction);
        max_tau = std::max(max_tau, a.extinction);
        min_a = std::min(min_a, a.albedo.x);
        max_a = std::max(max_a, a.albedo.x);
        bool overlaps = false;
        for (std::size_t j = 0; j < s.spheres.size() && !overlaps; ++j)
            overlaps = j != i && glm::length(a.center - s.spheres[j].center) < a.radius + s.spheres[j].radius;
        EXPECT_TRUE(overlaps) << "sphere " << i << " overlaps no other";
        EXPECT_GT(a.center.y + a.radius, 0.0) << "sphere " << i << " is buried in the ground";
    }
    EXPECT_GT(max_r, 2.0 * min_r);
    EXPECT_GT(max_tau, 2.0 * min_tau);
    EXPECT_GT(max_a - min_a, 0.2);
}

TEST(SceneFile, EmbeddedDefaultSceneMatchesThePresetFile) {
    // The build embeds presets/default.toml; a stale copy would mean the build missed an edit.
    const fs::path preset = fs::path(__FILE__).parent_path().parent_path() / "presets" / "default.toml";
    std::ifstream in(preset, std::ios::binary);
    ASSERT_TRUE(in) << preset;
    std::ostringstream text;
    text << in.rdbuf();
    EXPECT_EQ(default_scene_toml(), text.str());
}

// --- Rejections -----------------------------------------------------------------------------------

SceneFileError error_for(const std::string& text) {
    try {
        parse_scene_toml(text, "scene.toml");
    } catch (const SceneFileError& e) {
        return e;
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return SceneFileError("", 0, 0, "", "");
}

// The message must name the file, the line and the key path, and say what is wrong.
void expect_rejected(const std::string& text, int line, const std::string& key_path, const std::string& problem) {
    SCOPED_TRACE(text);
    const SceneFileError e = error_for(text);
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "scene.toml");
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key_path(), key_path) << what;
    EXPECT_EQ(what.rfind("scene.toml:" + std::to_string(line) + ": " + key_path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(problem), std::string::npos) << what << "\n  should contain: " << problem;
}

// A valid sphere whose radius sits on line 4 of the text.
std::string sphere(const std::string& radius_line) {
    return "# a sphere\n[[sphere]]\ncenter = [0, 0, 0]\n" + radius_line +
           "\nextinction = 1\nalbedo = [0.5, 0.5, 0.5]\n";
}

TEST(SceneFileErrors, MessageReadsFileLineKeyProblem) {
    const std::string text = sphere("radius = 1") + sphere("radius = -1");
    EXPECT_STREQ(error_for(text).what(), "scene.toml:10: sphere[1].radius: must be positive and finite (got -1)");
}

TEST(SceneFileErrors, UnknownKeysAreNamedWithSuggestions) {
    expect_rejected(sphere("raduis = 1"), 4, "sphere[0].raduis", "unknown key (did you mean \"radius\"?)");
    expect_rejected("[camra]\nwidth = 3\n", 1, "camra", "unknown table (did you mean \"camera\"?)");
    expect_rejected("[camera]\nwidht = 3\n", 2, "camera.widht", "did you mean \"width\"?");
    expect_rejected("[lighting]\nsun_dir = [0, -1, 0]\n", 2, "lighting.sun_dir", "unknown key");
    expect_rejected("[render]\nsamples = 4\n", 2, "render.samples", "allowed here: min_transmittance");
    expect_rejected("width = 3\n", 1, "width", "belongs under [camera]");
    // A key of one section written in another is pointed to its section, beside what the other reads.
    expect_rejected("[camera]\nshadows = true\n", 2, "camera.shadows",
                    "unknown key (it belongs under [lighting]; allowed here: position, look_at");
    expect_rejected("[lighting]\nsupersample = 2\n", 2, "lighting.supersample", "it belongs under [camera];");
    expect_rejected(sphere("diffuse = [1, 1, 1]"), 4, "sphere[0].diffuse", "it belongs in a [[box]] section;");
    expect_rejected("[[boxes]]\n", 1, "boxes", "unknown table (did you mean \"box\"?)");
    expect_rejected("[camera.lens]\nf = 1\n", 1, "camera.lens", "unknown table");
    // Of several unknown keys the first in the file is reported, not the first alphabetically.
    expect_rejected("[camera]\nzoom = 1\naperture = 2\n", 2, "camera.zoom", "unknown key");
}

TEST(SceneFileErrors, WrongTypes) {
    expect_rejected(sphere("radius = \"big\""), 4, "sphere[0].radius", "must be a number (got a string \"big\")");
    expect_rejected(sphere("radius = true"), 4, "sphere[0].radius", "must be a number");
    expect_rejected("\n[camera]\nposition = \"origin\"\n", 3, "camera.position", "must be an array of 3 numbers");
    expect_rejected("camera = 5\n", 1, "camera", "must be a table");
    expect_rejected("[box]\nmin = [0, 0, 0]\n", 1, "box", "write [[box]], not [box]");
    expect_rejected("sphere = [1, 2]\n", 1, "sphere[0]", "must be a table");
    expect_rejected("[camera]\nup = [0, \"1\", 0]\n", 2, "camera.up[1]", "must be a number");
}

TEST(SceneFileErrors, NanAndInfAnywhere) {
    expect_rejected(sphere("radius = nan"), 4, "sphere[0].radius", "must be finite (got nan)");
    expect_rejected(sphere("radius = inf"), 4, "sphere[0].radius", "must be finite (got inf)");
    expect_rejected("[lighting]\n\nsun = [1, -inf, 1]\n", 3, "lighting.sun[1]", "must be finite (got -inf)");
    expect_rejected("[render]\nmin_transmittance = -nan\n", 2, "render.min_transmittance", "must be finite");
    expect_rejected("[camera]\nfov_y_deg = +inf\n", 2, "camera.fov_y_deg", "must be finite");
}

TEST(SceneFileErrors, SphereValues) {
    expect_rejected(sphere("radius = 0"), 4, "sphere[0].radius", "must be positive and finite (got 0)");
    expect_rejected(sphere("radius = -0.0"), 4, "sphere[0].radius", "must be positive");
    expect_rejected(sphere("radius = 2e7"), 4, "sphere[0].radius", "absurd size");
    expect_rejected("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = -2\nalbedo = [0.5, 0.5, 0.5]\n", 4,
                    "sphere[0].extinction", "must not be negative (got -2)");
    expect_rejected("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1e10\nalbedo = [0.5, 0.5, 0.5]\n", 4,
                    "sphere[0].extinction", "absurd size");
    expect_rejected("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\nalbedo = [0.9, 1.5, 0.9]\n", 5,
                    "sphere[0].albedo[1]", "must be in [0, 1] (got 1.5)");
    expect_rejected("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\nalbedo = [-0.1, 0.5, 0.9]\n", 5,
                    "sphere[0].albedo[0]", "must be in [0, 1]");
    expect_rejected("[[sphere]]\ncenter = [0, 1e8, 0]\nradius = 1\nextinction = 1\nalbedo = [0.5, 0.5, 0.5]\n", 2,
                    "sphere[0].center[1]", "absurd size");
    // Every sphere key is required; the error points at the sphere's header.
    expect_rejected("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\n", 1, "sphere[0].albedo",
                    "missing");
    expect_rejected("\n[[sphere]]\ncenter = [0, 0, 0]\nextinction = 1\nalbedo = [1, 1, 1]\n", 2, "sphere[0].radius",
                    "missing");
}

TEST(SceneFileErrors, VectorsNeedExactlyThreeNumbers) {
    expect_rejected("[[sphere]]\ncenter = [0, 0]\nradius = 1\nextinction = 1\nalbedo = [0.5, 0.5, 0.5]\n", 2,
                    "sphere[0].center", "must be an array of exactly 3 numbers (got 2)");
    expect_rejected("[camera]\nup = [0, 1, 0, 0]\n", 2, "camera.up", "exactly 3 numbers (got 4)");
    // An element on its own line is reported on that line.
    expect_rejected("[lighting]\nambient = [\n  0.1,\n  -0.2,\n  0.3]\n", 4, "lighting.ambient[1]",
                    "must not be negative (got -0.2)");
}

// A scene that gives volumes but places no camera leaves the framing to the volume loader, and says so
// again when written back; placing either end of the view turns framing off.
TEST(SceneFile, VolumesWithoutACameraPlacementAreFramed) {
    const Scene framed = parse_scene_toml("[camera]\nfov_y_deg = 30.0\nwidth = 64\n[[vdb]]\nfile = \"c.vdb\"\n", "f.toml");
    EXPECT_TRUE(framed.frame_volumes);
    const Scene again = parse_scene_toml(scene_to_toml(framed), "again.toml");
    EXPECT_TRUE(again.frame_volumes);
    EXPECT_EQ(again.camera.fov_y_deg, 30.0);
    EXPECT_EQ(again.camera.width, 64);
    EXPECT_FALSE(parse_scene_toml("[[vdb]]\nfile = \"c.vdb\"\n[camera]\nlook_at = [1.0, 0.0, 0.0]\n", "p.toml").frame_volumes);
    EXPECT_FALSE(parse_scene_toml("[[vdb]]\nfile = \"c.vdb\"\n[camera]\nposition = [1.0, 0.0, 9.0]\n", "p.toml").frame_volumes);
    EXPECT_FALSE(parse_scene_toml("[camera]\nwidth = 64\n", "none.toml").frame_volumes);  // nothing to frame
}

TEST(SceneFileErrors, CameraValues) {
    expect_rejected("[camera]\nwidth = 0\n", 2, "camera.width", "must be between 1 and 16384 (got 0)");
    expect_rejected("[camera]\nwidth = 100000\n", 2, "camera.width", "must be between 1 and 16384 (got 100000)");
    expect_rejected("[camera]\nheight = 16385\n", 2, "camera.height", "must be between 1 and 16384");
    expect_rejected("[camera]\nwidth = 160.0\n", 2, "camera.width",
                    "must be an integer (got a floating-point number 160.0)");
    expect_rejected("[camera]\nwidth = 9223372036854775807\n", 2, "camera.width", "must be between 1 and 16384");
    expect_rejected("[camera]\nfov_y_deg = 0\n", 2, "camera.fov_y_deg", "must be in (0, 179] degrees (got 0)");
    expect_rejected("[camera]\nfov_y_deg = 179.5\n", 2, "camera.fov_y_deg", "must be in (0, 179] degrees");
    expect_rejected("[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, 3]\n", 3, "camera.look_at", "must differ");
    expect_rejected("[camera]\nposition = [0, 0.5, 0]\n", 2, "camera.position", "must differ");  // default look_at
    expect_rejected("[camera]\nposition = [0, 5, 0]\nlook_at = [0, 1, 0]\n", 3, "camera.up", "parallel");
    expect_rejected("[camera]\nup = [0, -2, 0]\nposition = [0, 5, 0]\nlook_at = [0, 1, 0]\n", 4, "camera.up",
                    "parallel");
    expect_rejected("[camera]\nup = [0, 0, 0]\n", 2, "camera.up", "must not be zero");
    expect_rejected("[camera]\nposition = [-1e8, 0, 0]\n", 2, "camera.position[0]", "absurd size");
    // Near-parallel but well defined is fine.
    EXPECT_NO_THROW(parse_scene_toml("[camera]\nposition = [0, 5, 0]\nlook_at = [0, 1, 0.01]\n", "ok.toml"));
    EXPECT_NO_THROW(parse_scene_toml("[camera]\nfov_y_deg = 179\nwidth = 16384\nheight = 1\n", "ok.toml"));
}

TEST(SceneFileErrors, LightingAndRenderValues) {
    expect_rejected("[lighting]\nsun_direction = [0, 0, 0]\n", 2, "lighting.sun_direction", "must not be zero");
    expect_rejected("[lighting]\nsun = [1, 1, -0.5]\n", 2, "lighting.sun[2]", "must not be negative (got -0.5)");
    expect_rejected("[lighting]\nbackground = [0, -1, 0]\n", 2, "lighting.background[1]", "must not be negative");
    expect_rejected("[lighting]\nambient = [1e12, 0, 0]\n", 2, "lighting.ambient[0]", "absurd size");
    expect_rejected("[render]\nmin_transmittance = 1\n", 2, "render.min_transmittance", "must be in [0, 1) (got 1)");
    expect_rejected("[render]\nmin_transmittance = -0.1\n", 2, "render.min_transmittance", "must be in [0, 1)");
}

TEST(SceneFileErrors, BoxValues) {
    expect_rejected("[[box]]\nmin = [0, 0, 0]\nmax = [1, 0, 1]\nradiance = [1, 1, 1]\n", 3, "box[0].max",
                    "must exceed min on every axis (max.y = 0, min.y = 0)");
    expect_rejected("[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradiance = [1, 1, 1]\n"
                    "[[box]]\nmin = [0, 0, 5]\nmax = [1, 1, 1]\nradiance = [1, 1, 1]\n",
                    7, "box[1].max", "max.z = 1, min.z = 5");
    expect_rejected("[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradiance = [-1, 1, 1]\n", 4, "box[0].radiance[0]",
                    "must not be negative");
    expect_rejected("[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n", 1, "box[0].radiance", "missing");
    expect_rejected("[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradiance = [1, 1, 1]\nradiant = 1\n", 5,
                    "box[0].radiant", "did you mean \"radiance\"?");
}

// The light keys (docs/accuracy.md, "Light through the smoke"): read, written back only where they differ
// from their defaults (so older scenes write the same text), and refused with a named problem.
TEST(SceneFile, LightKeysAreReadAndWrittenBack) {
    const std::string text =
        "[camera]\nsupersample = 3\n[lighting]\nshadows = true\n[render]\nshadow_technique = \"per-sphere\"\n"
        "[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradiance = [0, 0, 0]\ndiffuse = [0.5, 0.25, 1]\n"
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\nalbedo = [1, 1, 1]\nemission = [4, 2.5, 0]\n";
    const Scene s = parse_scene_toml(text, "light.toml");
    EXPECT_EQ(s.camera.supersample, 3);
    EXPECT_TRUE(s.lighting.shadows);
    EXPECT_EQ(s.render.shadow_technique, ShadowTechnique::PerSphere);
    expect_vec(s.boxes[0].diffuse, 0.5, 0.25, 1.0);
    expect_vec(s.spheres[0].emission, 4.0, 2.5, 0.0);
    const std::string written = scene_to_toml(s);
    expect_identical(parse_scene_toml(written, "written.toml"), s);
    EXPECT_NE(written.find("shadows = true\n"), std::string::npos) << written;
    EXPECT_NE(written.find("supersample = 3\n"), std::string::npos) << written;

    // Without the keys: the defaults, and none of them in the written text.
    const Scene plain = parse_scene_toml(kEveryKey, "every.toml");
    EXPECT_EQ(plain.camera.supersample, 1);
    EXPECT_FALSE(plain.lighting.shadows);
    EXPECT_EQ(plain.boxes[0].diffuse, glm::dvec3(0.0));
    EXPECT_EQ(plain.spheres[0].emission, glm::dvec3(0.0));
    const std::string plain_text = scene_to_toml(plain);
    EXPECT_EQ(plain.render.shadow_technique, ShadowTechnique::Accurate);
    for (const char* key : {"supersample", "shadows", "diffuse", "emission", "shadow_technique"})
        EXPECT_EQ(plain_text.find(key), std::string::npos) << key << " written for a scene without it";
    EXPECT_FALSE(parse_scene_toml("[lighting]\nshadows = false\n", "off.toml").lighting.shadows);
}

TEST(SceneFileErrors, LightKeyValues) {
    expect_rejected("[lighting]\nshadows = \"yes\"\n", 2, "lighting.shadows",
                    "must be true or false (got a string \"yes\")");
    expect_rejected("[lighting]\nshadows = 1\n", 2, "lighting.shadows", "must be true or false");
    expect_rejected("[render]\nshadow_technique = \"fast\"\n", 2, "render.shadow_technique", "accurate");
    expect_rejected("[camera]\nsupersample = 0\n", 2, "camera.supersample", "must be between 1 and 8 (got 0)");
    expect_rejected("[camera]\nsupersample = 99\n", 2, "camera.supersample", "must be between 1 and 8 (got 99)");
    expect_rejected("[camera]\nsupersample = 2.0\n", 2, "camera.supersample", "must be an integer");
    const std::string sphere_head = "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\nalbedo = [1, 1, 1]\n";
    expect_rejected(sphere_head + "emission = [1, -0.5, 0]\n", 6, "sphere[0].emission[1]",
                    "must not be negative (got -0.5)");
    expect_rejected(sphere_head + "emission = [nan, 0, 0]\n", 6, "sphere[0].emission[0]", "must be finite (got nan)");
    expect_rejected(sphere_head + "emission = 3\n", 6, "sphere[0].emission", "must be an array of 3 numbers");
    const std::string box_head = "[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradiance = [1, 1, 1]\n";
    expect_rejected(box_head + "diffuse = [-1, 0, 0]\n", 5, "box[0].diffuse[0]", "must be in [0, 1] (got -1)");
    expect_rejected(box_head + "diffuse = [0, 0, nan]\n", 5, "box[0].diffuse[2]", "must be finite (got nan)");
    expect_rejected(box_head + "diffuse = [0, 2, 0]\n", 5, "box[0].diffuse[1]", "must be in [0, 1] (got 2)");
}

TEST(SceneFileErrors, TooManyBoxes) {
    // The count is checked before the elements, so placeholders are enough to reach the limit.
    std::string at_limit = "box = [";
    for (std::size_t i = 0; i < kMaxBoxes; ++i) at_limit += "0,";
    at_limit += "]\n";
    expect_rejected(at_limit, 1, "box[0]", "must be a table");  // exactly the limit passes the count
    std::string over = "\n";  // appended: "\n" + std::string&& draws GCC 12's false -Wrestrict warning
    over.append(at_limit, 0, at_limit.size() - 2).append("0,]\n");
    expect_rejected(over, 2, "box", "too many boxes (got 100001, the limit is 100000)");
}

// A [[vdb]] table whose file is on line 3, with `line` added on line 4.
std::string vdb(const std::string& line) { return "# a volume\n[[vdb]]\nfile = \"cloud.vdb\"\n" + line + "\n"; }

TEST(SceneFileErrors, VdbKeysAndTables) {
    expect_rejected("\n[[vdb]]\ngrid = \"density\"\n", 2, "vdb[0].file",
                    "missing (each [[vdb]] needs file: a .vdb path or builtin:NAME)");
    expect_rejected(vdb("tolerence = 0.1"), 4, "vdb[0].tolerence", "unknown key (did you mean \"tolerance\"?)");
    expect_rejected(vdb("radius = 1"), 4, "vdb[0].radius",
                    "unknown key (it belongs in a [[sphere]] section; allowed here: file, grid, albedo_grid");
    expect_rejected("[[vbd]]\nfile = \"a.vdb\"\n", 1, "vbd", "unknown table (did you mean \"vdb\"?)");
    expect_rejected("[vdb]\nfile = \"a.vdb\"\n", 1, "vdb", "write [[vdb]], not [vdb]");
    expect_rejected("albedo_grid = \"tint\"\n", 1, "albedo_grid", "it belongs in a [[vdb]] section");
    expect_rejected(vdb("") + "[[vdb]]\nfile = \"b.vdb\"\nmax_spheres = 0\n", 7, "vdb[1].max_spheres",
                    "must be between 1 and 50000000 (got 0)");
}

TEST(SceneFileErrors, VdbValues) {
    expect_rejected("[[vdb]]\nfile = \"\"\n", 2, "vdb[0].file", "must not be empty");
    expect_rejected("[[vdb]]\nfile = 3\n", 2, "vdb[0].file", "must be a string (got an integer 3)");
    expect_rejected("[[vdb]]\nfile = \"a\\nb.vdb\"\n", 2, "vdb[0].file", "must be one line");
    expect_rejected(vdb("grid = \"\""), 4, "vdb[0].grid", "must not be empty (it names a grid in the file)");
    expect_rejected(vdb("grid = 1.5"), 4, "vdb[0].grid", "must be a string");
    expect_rejected(vdb("albedo_grid = \"a\\nb\""), 4, "vdb[0].albedo_grid", "must be one line of text");
    expect_rejected(vdb("extinction_scale = 0"), 4, "vdb[0].extinction_scale", "must be positive (got 0)");
    expect_rejected(vdb("extinction_scale = -2"), 4, "vdb[0].extinction_scale", "must be positive (got -2)");
    expect_rejected(vdb("extinction_scale = 2e9"), 4, "vdb[0].extinction_scale", "absurd size: must be at most 1e9");
    expect_rejected(vdb("extinction_scale = nan"), 4, "vdb[0].extinction_scale", "must be finite (got nan)");
    expect_rejected(vdb("albedo = 1.5"), 4, "vdb[0].albedo", "must be in [0, 1] (got 1.5)");
    expect_rejected(vdb("albedo = [0.5, -0.1, 0.5]"), 4, "vdb[0].albedo[1]", "must be in [0, 1] (got -0.1)");
    expect_rejected(vdb("albedo = [0.5, 0.5]"), 4, "vdb[0].albedo", "exactly 3 numbers (got 2)");
    expect_rejected(vdb("albedo = \"grey\""), 4, "vdb[0].albedo", "must be a number or [r, g, b] (got a string");
    expect_rejected(vdb("tolerance = 0"), 4, "vdb[0].tolerance", "must be in (0, 1] (got 0)");
    expect_rejected(vdb("tolerance = 1.5"), 4, "vdb[0].tolerance", "must be in (0, 1] (got 1.5)");
    expect_rejected(vdb("tolerance = inf"), 4, "vdb[0].tolerance", "must be finite (got inf)");
    expect_rejected(vdb("max_spheres = 0"), 4, "vdb[0].max_spheres", "must be between 1 and 50000000 (got 0)");
    expect_rejected(vdb("max_spheres = 50000001"), 4, "vdb[0].max_spheres", "(got 50000001)");
    expect_rejected(vdb("max_spheres = 100.0"), 4, "vdb[0].max_spheres", "must be an integer");
    // Both: the later of the two is pointed at, and the message names both.
    expect_rejected(vdb("tolerance = 0.1\nmax_spheres = 100"), 5, "vdb[0].max_spheres",
                    "give tolerance or max_spheres, not both");
    expect_rejected(vdb("max_spheres = 100\ntolerance = 0.1"), 5, "vdb[0].tolerance",
                    "give tolerance or max_spheres, not both");
    EXPECT_NO_THROW(parse_scene_toml(vdb("tolerance = 1\nalbedo = 0\nextinction_scale = 1e9"), "ok.toml"));
    EXPECT_NO_THROW(parse_scene_toml(vdb("max_spheres = 50000000\nalbedo = [1, 0, 1]"), "ok.toml"));
}

TEST(SceneFileErrors, VdbTransform) {
    expect_rejected(vdb("scale = 0"), 4, "vdb[0].scale", "scale must be positive, finite and at most");
    expect_rejected(vdb("scale = -1"), 4, "vdb[0].scale", "(got -1)");
    expect_rejected(vdb("scale = 2e7"), 4, "vdb[0].scale", "(got 2e+07)");
    expect_rejected(vdb("scale = inf"), 4, "vdb[0].scale", "must be finite (got inf)");
    expect_rejected(vdb("scale = [1, 1, 1]"), 4, "vdb[0].scale", "must be a number");
    expect_rejected(vdb("translate = [0, 2e7, 0]"), 4, "vdb[0].translate", "translate components must be finite");
    expect_rejected(vdb("translate = [0, nan, 0]"), 4, "vdb[0].translate[1]", "must be finite (got nan)");
    expect_rejected(vdb("translate = [1, 2]"), 4, "vdb[0].translate", "exactly 3 numbers (got 2)");
    expect_rejected(vdb("rotate = [0, 0, 4000]"), 4, "vdb[0].rotate", "rotate components must be finite degrees");
    expect_rejected(vdb("rotate = 90"), 4, "vdb[0].rotate", "must be an array of 3 numbers");
    EXPECT_NO_THROW(parse_scene_toml(vdb("translate = [-1e7, 0, 1e7]\nscale = 1e7\nrotate = [-3600, 0, 3600]"),
                                     "ok.toml"));
}

TEST(SceneFileErrors, MalformedTomlReportsLineAndColumn) {
    const SceneFileError e = error_for("[camera]\nwidth = 160\nheight = = 3\n");
    const std::string what = e.what();
    EXPECT_EQ(e.line(), 3) << what;
    EXPECT_GT(e.column(), 0) << what;
    EXPECT_EQ(what.rfind("scene.toml:3:", 0), 0u) << what;
    EXPECT_NE(what.find("invalid TOML"), std::string::npos) << what;

    const SceneFileError duplicate = error_for("[camera]\nwidth = 1\n\nwidth = 2\n");
    EXPECT_EQ(duplicate.line(), 4) << duplicate.what();

    const SceneFileError unclosed = error_for("[[sphere]]\ncenter = [0, 0, 0\nradius = 1\n");
    EXPECT_GE(unclosed.line(), 2) << unclosed.what();
}

// --- Files ----------------------------------------------------------------------------------------

class SceneFileOnDisk : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("brume_scene_file_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(SceneFileOnDisk, LoadsAFileAndRecordsItsPath) {
    const fs::path path = dir_ / "every.toml";
    std::ofstream(path) << kEveryKey;
    const Scene s = load_scene_file(path);
    EXPECT_EQ(s.source, path.string());
    expect_identical(s, parse_scene_toml(kEveryKey, "every.toml"));
}

TEST_F(SceneFileOnDisk, ErrorsInAFileNameThePath) {
    const fs::path path = dir_ / "bad.toml";
    std::ofstream(path) << sphere("radius = -3");
    try {
        load_scene_file(path);
        FAIL() << "accepted a negative radius";
    } catch (const SceneFileError& e) {
        EXPECT_EQ(std::string(e.what()), path.string() + ":4: sphere[0].radius: must be positive and finite (got -3)");
    }
}

TEST_F(SceneFileOnDisk, VdbFilesAreFoundBesideTheScene) {
    fs::create_directories(dir_ / "scenes" / "grids");
    std::ofstream(dir_ / "scenes" / "grids" / "cloud.vdb") << "not really a vdb";
    const fs::path path = dir_ / "scenes" / "cloud.toml";
    std::ofstream(path) << "[[vdb]]\nfile = \"grids/cloud.vdb\"\n[[vdb]]\nfile = \"builtin:sheet\"\n";
    const Scene s = load_scene_file(path);
    ASSERT_EQ(s.volumes.size(), 2u);
    for (const VdbVolume& v : s.volumes) EXPECT_EQ(v.source.base_dir, (dir_ / "scenes").string());
    EXPECT_TRUE(fs::exists(fs::path(s.volumes[0].source.base_dir) / s.volumes[0].source.file));
    EXPECT_EQ(s.volumes[0].source.file, "grids/cloud.vdb") << "the file is kept as written";

    // A relative scene path gives a relative base_dir, still right from the same working directory.
    const fs::path previous = fs::current_path();
    fs::current_path(dir_);
    Scene relative;
    EXPECT_NO_THROW(relative = load_scene_file(fs::path("scenes") / "cloud.toml"));
    const bool found = fs::exists(fs::path(relative.volumes.at(0).source.base_dir) / relative.volumes[0].source.file);
    const Scene here = load_scene_file(fs::path("scenes/..") / "scenes" / "cloud.toml");
    fs::current_path(previous);
    EXPECT_EQ(relative.volumes[0].source.base_dir, "scenes");
    EXPECT_TRUE(found);
    EXPECT_EQ(here.volumes[0].source.base_dir, "scenes/../scenes");
    // Written back, the base_dir is not: a copy elsewhere looks beside itself.
    EXPECT_EQ(scene_to_toml(s).find(dir_.string()), std::string::npos);
}

TEST_F(SceneFileOnDisk, MissingFileNamesTheFileAndTheReason) {
    const fs::path path = dir_ / "no_such_scene.toml";
    try {
        load_scene_file(path);
        FAIL() << "loaded a missing file";
    } catch (const SceneFileError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.file(), path.string());
        EXPECT_NE(what.find(path.string()), std::string::npos) << what;
        EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
    }
    EXPECT_THROW(load_scene_file(dir_), SceneFileError);  // a directory is not a scene
}

}  // namespace
}  // namespace brume
