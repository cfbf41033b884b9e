// Preset files: every shipped preset parses and round-trips, every field lands where it belongs, every
// bad input is rejected with the file, line and key path, and names resolve to files or built-ins.
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/emitters.h"
#include "sim/layers_scene.h"
#include "sim/preset_file.h"
#include "sim/scene_file.h"
#include "tests/scratch_dir.h"

#include <gtest/gtest.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

namespace brume {
namespace {

namespace fs = std::filesystem;

const fs::path kPresetDir = fs::path(__FILE__).parent_path().parent_path() / "presets";
const std::vector<std::string> kShipped{"campfire", "crossing", "explosion", "fog-bank", "ground-fog",
                                        "layers",   "low-sun",  "plume",     "pop",       "vdb-cloud"};

// Every key of the schema set to something other than its default.
constexpr const char* kEveryKey = R"([preset]
name = "every-key"
description = "Every key set"

[timeline]
fps = 30.0
duration = 2.5
substeps = 3
preroll = 1.5
seed = 12345678901
max_particles = 777
resolution = [400, 300]

[camera]
position = [1.0, 2.0, 8.0]
look_at = [0.0, 1.0, 0.0]
width = 100
height = 50

[lighting]
ambient = [0.1, 0.2, 0.3]

[render]
min_transmittance = 0.001

[[box]]
min = [-1, -1, -1]
max = [1, 0, 1]
radiance = [0.1, 0.1, 0.1]

[[sphere]]
center = [0, 3, 0]
radius = 0.5
extinction = 2
albedo = [0.5, 0.6, 0.7]

[[vdb]]
file = "grids/cloud.vdb"
grid = "smoke"
albedo_grid = "tint"
extinction_scale = 3.5
albedo = [0.8, 0.85, 0.9]
max_spheres = 5000
translate = [0, 2, -1]
scale = 0.5
rotate = [0, 90, 0]

[[emitter]]
name = "disc one"
shape = "disc"
center = [0.5, 1.0, -0.5]
radius = 0.25
normal = [0.0, 0.0, 1.0]
rate = 40.5
start = 0.5
stop = 2.0
bursts = [{ time = 0.5, count = 200 }, { time = 1.25, count = 3 }]
direction = [1, 2, 0]
speed = [0.5, 1.5]
cone_deg = 12.5
jitter = 0.125
lifetime = [1.0, 3.0]
particle_radius = [0.05, 0.15]
extinction = [2.0, 4.0]
albedo = { min = [0.1, 0.2, 0.3], max = [0.4, 0.5, 0.6] }

[emitter.curves]
radius_growth = 2.5
fade_in = 0.25
fade_out = 0.5
albedo_ramp = [{ age = 0.0, multiplier = [0.5, 0.5, 0.5] }, { age = 0.75, multiplier = [1, 0.9, 0.8] }]

[[emitter]]
shape = "box"
half_extent = [1, 2, 3]
speed = 2.0
albedo = [0.7, 0.8, 0.9]

[[emitter]]
shape = "sphere"
radius = 1.5
lifetime = 4

[[emitter]]
name = "seeded"
shape = "density"
file = "builtin:cloud:32"
grid = "density2"
translate = [0.5, 1.5, -0.25]
scale = 2
rotate = [15, 45, -5]
rate = 100

[[force]]
type = "gravity"
vector = [0, -9.81, 0]

[[force]]
type = "buoyancy"
strength = -0.5

[[force]]
type = "wind"
vector = [2, 0, 1]
strength = 0.3

[[force]]
type = "drag"
strength = 0.2

[[force]]
type = "turbulence"
strength = 1.5
scale = 0.7
speed = 0.4
octaves = 3
lacunarity = 2.5
gain = 0.6

[[force]]
type = "vortex"
strength = -2.0
center = [1, 0, 1]
axis = [0, 1, 0.5]
radius = 0.75

[camera_path]
type = "keyframes"
keys = [
  { time = 0.0, position = [0, 1, 6], look_at = [0, 1, 0] },
  { time = 1.5, position = [2, 1, 5], look_at = [0, 1.5, 0] },
]

[render_settings]
method = "reference"
exposure = -1.5
)";

void expect_vec(const glm::dvec3& v, double x, double y, double z) {
    EXPECT_EQ(v.x, x);
    EXPECT_EQ(v.y, y);
    EXPECT_EQ(v.z, z);
}

// Bitwise, so -0.0 and 0.0 count as different and any printing loss shows.
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const glm::dvec3& a, const glm::dvec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }
bool same(const Range& a, const Range& b) { return same(a.min, b.min) && same(a.max, b.max); }

void expect_identical(const Scene& a, const Scene& b) {
    EXPECT_TRUE(same(a.camera.position, b.camera.position));
    EXPECT_TRUE(same(a.camera.look_at, b.camera.look_at));
    EXPECT_TRUE(same(a.camera.up, b.camera.up));
    EXPECT_TRUE(same(a.camera.fov_y_deg, b.camera.fov_y_deg));
    EXPECT_EQ(a.camera.width, b.camera.width);
    EXPECT_EQ(a.camera.height, b.camera.height);
    EXPECT_EQ(a.camera.supersample, b.camera.supersample);
    EXPECT_EQ(a.lighting.shadows, b.lighting.shadows);
    EXPECT_TRUE(same(a.lighting.ambient, b.lighting.ambient));
    EXPECT_TRUE(same(a.lighting.sun, b.lighting.sun));
    EXPECT_TRUE(same(a.lighting.sun_direction, b.lighting.sun_direction));
    EXPECT_TRUE(same(a.lighting.background, b.lighting.background));
    EXPECT_TRUE(same(a.render.min_transmittance, b.render.min_transmittance));
    EXPECT_EQ(a.render.shadow_technique, b.render.shadow_technique);
    ASSERT_EQ(a.boxes.size(), b.boxes.size());
    for (std::size_t i = 0; i < a.boxes.size(); ++i) {
        EXPECT_TRUE(same(a.boxes[i].min, b.boxes[i].min) && same(a.boxes[i].max, b.boxes[i].max) &&
                    same(a.boxes[i].radiance, b.boxes[i].radiance) && same(a.boxes[i].diffuse, b.boxes[i].diffuse))
            << "box " << i;
    }
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (std::size_t i = 0; i < a.spheres.size(); ++i) {
        const Sphere &s = a.spheres[i], &t = b.spheres[i];
        EXPECT_TRUE(same(s.center, t.center) && same(s.radius, t.radius) && same(s.extinction, t.extinction) &&
                    same(s.albedo, t.albedo) && same(s.emission, t.emission))
            << "sphere " << i;
    }
    ASSERT_EQ(a.volumes.size(), b.volumes.size());
    for (std::size_t i = 0; i < a.volumes.size(); ++i) {
        const VdbVolume &v = a.volumes[i], &w = b.volumes[i];
        EXPECT_EQ(v.source.file, w.source.file) << "volume " << i;
        EXPECT_EQ(v.source.grid, w.source.grid) << "volume " << i;
        EXPECT_EQ(v.albedo_grid, w.albedo_grid) << "volume " << i;
        EXPECT_TRUE(same(v.extinction_scale, w.extinction_scale) && same(v.albedo, w.albedo)) << "volume " << i;
        EXPECT_EQ(v.max_spheres, w.max_spheres) << "volume " << i;
        if (v.max_spheres == 0) {  // with a sphere budget the tolerance is unused, and not written
            EXPECT_TRUE(same(v.tolerance, w.tolerance)) << "volume " << i;
        }
        EXPECT_TRUE(same(v.transform.translate, w.transform.translate) && same(v.transform.scale, w.transform.scale) &&
                    same(v.transform.rotate_deg, w.transform.rotate_deg))
            << "volume " << i;
    }
}

void expect_identical(const Preset& a, const Preset& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.description, b.description);
    expect_identical(a.scene, b.scene);
    EXPECT_TRUE(same(a.timeline.fps, b.timeline.fps));
    EXPECT_TRUE(same(a.timeline.duration, b.timeline.duration));
    EXPECT_EQ(a.timeline.substeps, b.timeline.substeps);
    EXPECT_TRUE(same(a.timeline.preroll, b.timeline.preroll));
    EXPECT_EQ(a.timeline.seed, b.timeline.seed);
    EXPECT_EQ(a.timeline.max_particles, b.timeline.max_particles);
    ASSERT_EQ(a.emitters.size(), b.emitters.size());
    for (std::size_t i = 0; i < a.emitters.size(); ++i) {
        SCOPED_TRACE("emitter " + std::to_string(i));
        const EmitterDesc &e = a.emitters[i], &f = b.emitters[i];
        EXPECT_EQ(e.name, f.name);
        EXPECT_EQ(e.shape, f.shape);
        EXPECT_TRUE(same(e.center, f.center));
        EXPECT_TRUE(same(e.radius, f.radius));
        EXPECT_TRUE(same(e.half_extent, f.half_extent));
        EXPECT_TRUE(same(e.normal, f.normal));
        // base_dir is where a file was read from, not what it says: not compared.
        EXPECT_EQ(e.density_source.file, f.density_source.file);
        EXPECT_EQ(e.density_source.grid, f.density_source.grid);
        EXPECT_TRUE(same(e.density_transform.translate, f.density_transform.translate));
        EXPECT_TRUE(same(e.density_transform.scale, f.density_transform.scale));
        EXPECT_TRUE(same(e.density_transform.rotate_deg, f.density_transform.rotate_deg));
        EXPECT_TRUE(same(e.rate, f.rate));
        ASSERT_EQ(e.bursts.size(), f.bursts.size());
        for (std::size_t k = 0; k < e.bursts.size(); ++k) {
            EXPECT_TRUE(same(e.bursts[k].time, f.bursts[k].time));
            EXPECT_EQ(e.bursts[k].count, f.bursts[k].count);
        }
        EXPECT_TRUE(same(e.start, f.start));
        EXPECT_TRUE(same(e.stop, f.stop));
        EXPECT_TRUE(same(e.direction, f.direction));
        EXPECT_TRUE(same(e.speed, f.speed));
        EXPECT_TRUE(same(e.cone_deg, f.cone_deg));
        EXPECT_TRUE(same(e.jitter, f.jitter));
        EXPECT_TRUE(same(e.lifetime, f.lifetime));
        EXPECT_TRUE(same(e.radius_range, f.radius_range));
        EXPECT_TRUE(same(e.extinction, f.extinction));
        EXPECT_TRUE(same(e.albedo.min, f.albedo.min));
        EXPECT_TRUE(same(e.albedo.max, f.albedo.max));
        EXPECT_TRUE(same(e.emission, f.emission));
        EXPECT_TRUE(same(e.curves.radius_growth, f.curves.radius_growth));
        EXPECT_TRUE(same(e.curves.fade_in, f.curves.fade_in));
        EXPECT_TRUE(same(e.curves.fade_out, f.curves.fade_out));
        ASSERT_EQ(e.curves.albedo_ramp.size(), f.curves.albedo_ramp.size());
        for (std::size_t k = 0; k < e.curves.albedo_ramp.size(); ++k) {
            EXPECT_TRUE(same(e.curves.albedo_ramp[k].age, f.curves.albedo_ramp[k].age));
            EXPECT_TRUE(same(e.curves.albedo_ramp[k].multiplier, f.curves.albedo_ramp[k].multiplier));
        }
        ASSERT_EQ(e.curves.emission_ramp.size(), f.curves.emission_ramp.size());
        for (std::size_t k = 0; k < e.curves.emission_ramp.size(); ++k) {
            EXPECT_TRUE(same(e.curves.emission_ramp[k].age, f.curves.emission_ramp[k].age));
            EXPECT_TRUE(same(e.curves.emission_ramp[k].multiplier, f.curves.emission_ramp[k].multiplier));
        }
    }
    ASSERT_EQ(a.forces.size(), b.forces.size());
    for (std::size_t i = 0; i < a.forces.size(); ++i) {
        SCOPED_TRACE("force " + std::to_string(i));
        const ForceDesc &f = a.forces[i], &g = b.forces[i];
        EXPECT_EQ(f.kind, g.kind);
        EXPECT_TRUE(same(f.vector, g.vector));
        EXPECT_TRUE(same(f.strength, g.strength));
        EXPECT_TRUE(same(f.scale, g.scale));
        EXPECT_TRUE(same(f.speed, g.speed));
        EXPECT_EQ(f.octaves, g.octaves);
        EXPECT_TRUE(same(f.lacunarity, g.lacunarity));
        EXPECT_TRUE(same(f.gain, g.gain));
        EXPECT_TRUE(same(f.center, g.center));
        EXPECT_TRUE(same(f.axis, g.axis));
        EXPECT_TRUE(same(f.radius, g.radius));
    }
    const CameraPath &p = a.camera_path, &q = b.camera_path;
    EXPECT_EQ(p.kind, q.kind);
    ASSERT_EQ(p.keys.size(), q.keys.size());
    for (std::size_t k = 0; k < p.keys.size(); ++k) {
        EXPECT_TRUE(same(p.keys[k].time, q.keys[k].time));
        EXPECT_TRUE(same(p.keys[k].position, q.keys[k].position));
        EXPECT_TRUE(same(p.keys[k].look_at, q.keys[k].look_at));
    }
    EXPECT_TRUE(same(p.orbit_center, q.orbit_center));
    EXPECT_TRUE(same(p.orbit_radius, q.orbit_radius));
    EXPECT_TRUE(same(p.orbit_height, q.orbit_height));
    EXPECT_TRUE(same(p.orbit_start_deg, q.orbit_start_deg));
    EXPECT_TRUE(same(p.orbit_deg_per_second, q.orbit_deg_per_second));
    EXPECT_EQ(a.render.method, b.render.method);
    EXPECT_TRUE(same(a.render.exposure, b.render.exposure));
}

std::string file_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// --- Reading --------------------------------------------------------------------------------------

TEST(PresetFile, EveryKeyLandsInItsField) {
    const Preset p = parse_preset_toml(kEveryKey, "every.toml");
    EXPECT_EQ(p.name, "every-key");
    EXPECT_EQ(p.description, "Every key set");
    EXPECT_EQ(p.scene.source, "every.toml");

    EXPECT_EQ(p.timeline.fps, 30.0);
    EXPECT_EQ(p.timeline.duration, 2.5);
    EXPECT_EQ(p.timeline.substeps, 3);
    EXPECT_EQ(p.timeline.preroll, 1.5);
    EXPECT_EQ(p.timeline.seed, 12345678901u);
    EXPECT_EQ(p.timeline.max_particles, 777u);
    EXPECT_EQ(p.timeline.frame_count(), 75);
    // resolution overrides [camera] width and height.
    EXPECT_EQ(p.scene.camera.width, 400);
    EXPECT_EQ(p.scene.camera.height, 300);

    // The scene sections are read as in a scene file.
    expect_vec(p.scene.camera.position, 1.0, 2.0, 8.0);
    expect_vec(p.scene.lighting.ambient, 0.1, 0.2, 0.3);
    EXPECT_EQ(p.scene.render.min_transmittance, 0.001);
    ASSERT_EQ(p.scene.boxes.size(), 1u);
    ASSERT_EQ(p.scene.spheres.size(), 1u);
    EXPECT_EQ(p.scene.spheres[0].radius, 0.5);

    ASSERT_EQ(p.scene.volumes.size(), 1u);
    const VdbVolume& v = p.scene.volumes[0];
    EXPECT_EQ(v.source.file, "grids/cloud.vdb");
    EXPECT_EQ(v.source.grid, "smoke");
    EXPECT_EQ(v.source.base_dir, "");
    EXPECT_EQ(v.albedo_grid, "tint");
    EXPECT_EQ(v.extinction_scale, 3.5);
    expect_vec(v.albedo, 0.8, 0.85, 0.9);
    EXPECT_EQ(v.max_spheres, 5000u);
    expect_vec(v.transform.translate, 0.0, 2.0, -1.0);
    EXPECT_EQ(v.transform.scale, 0.5);
    expect_vec(v.transform.rotate_deg, 0.0, 90.0, 0.0);

    ASSERT_EQ(p.emitters.size(), 4u);
    const EmitterDesc& e = p.emitters[0];
    EXPECT_EQ(e.name, "disc one");
    EXPECT_EQ(e.shape, EmitterShape::Disc);
    expect_vec(e.center, 0.5, 1.0, -0.5);
    EXPECT_EQ(e.radius, 0.25);
    expect_vec(e.normal, 0.0, 0.0, 1.0);
    EXPECT_EQ(e.rate, 40.5);
    EXPECT_EQ(e.start, 0.5);
    EXPECT_EQ(e.stop, 2.0);
    ASSERT_EQ(e.bursts.size(), 2u);
    EXPECT_EQ(e.bursts[0].time, 0.5);
    EXPECT_EQ(e.bursts[0].count, 200u);
    EXPECT_EQ(e.bursts[1].time, 1.25);
    EXPECT_EQ(e.bursts[1].count, 3u);
    expect_vec(e.direction, 1.0, 2.0, 0.0);
    EXPECT_EQ(e.speed.min, 0.5);
    EXPECT_EQ(e.speed.max, 1.5);
    EXPECT_EQ(e.cone_deg, 12.5);
    EXPECT_EQ(e.jitter, 0.125);
    EXPECT_EQ(e.lifetime.min, 1.0);
    EXPECT_EQ(e.lifetime.max, 3.0);
    EXPECT_EQ(e.radius_range.min, 0.05);  // particle_radius
    EXPECT_EQ(e.radius_range.max, 0.15);
    EXPECT_EQ(e.extinction.min, 2.0);
    EXPECT_EQ(e.extinction.max, 4.0);
    expect_vec(e.albedo.min, 0.1, 0.2, 0.3);
    expect_vec(e.albedo.max, 0.4, 0.5, 0.6);
    EXPECT_EQ(e.curves.radius_growth, 2.5);
    EXPECT_EQ(e.curves.fade_in, 0.25);
    EXPECT_EQ(e.curves.fade_out, 0.5);
    ASSERT_EQ(e.curves.albedo_ramp.size(), 2u);
    EXPECT_EQ(e.curves.albedo_ramp[1].age, 0.75);
    expect_vec(e.curves.albedo_ramp[1].multiplier, 1.0, 0.9, 0.8);

    // One number for a range, a plain colour for an albedo; defaults elsewhere.
    const EmitterDesc& box = p.emitters[1];
    EXPECT_EQ(box.shape, EmitterShape::Box);
    expect_vec(box.half_extent, 1.0, 2.0, 3.0);
    EXPECT_EQ(box.speed.min, 2.0);
    EXPECT_EQ(box.speed.max, 2.0);
    expect_vec(box.albedo.min, 0.7, 0.8, 0.9);
    expect_vec(box.albedo.max, 0.7, 0.8, 0.9);
    EXPECT_TRUE(std::isinf(box.stop));
    EXPECT_TRUE(box.bursts.empty());
    EXPECT_EQ(p.emitters[2].shape, EmitterShape::Sphere);
    EXPECT_EQ(p.emitters[2].radius, 1.5);
    EXPECT_EQ(p.emitters[2].lifetime.min, 4.0);  // an integer read as a float
    const EmitterDesc& seeded = p.emitters[3];
    EXPECT_EQ(seeded.name, "seeded");
    EXPECT_EQ(seeded.shape, EmitterShape::Density);
    EXPECT_EQ(seeded.density_source.file, "builtin:cloud:32");
    EXPECT_EQ(seeded.density_source.grid, "density2");
    EXPECT_EQ(seeded.density_source.base_dir, "");
    expect_vec(seeded.density_transform.translate, 0.5, 1.5, -0.25);
    EXPECT_EQ(seeded.density_transform.scale, 2.0);
    expect_vec(seeded.density_transform.rotate_deg, 15.0, 45.0, -5.0);
    EXPECT_EQ(seeded.density, nullptr) << "parsing reads no grid: load_emitter_densities does";
    EXPECT_EQ(seeded.rate, 100.0);

    ASSERT_EQ(p.forces.size(), 6u);
    EXPECT_EQ(p.forces[0].kind, ForceKind::Gravity);
    expect_vec(p.forces[0].vector, 0.0, -9.81, 0.0);
    EXPECT_EQ(p.forces[1].kind, ForceKind::Buoyancy);
    EXPECT_EQ(p.forces[1].strength, -0.5);
    EXPECT_EQ(p.forces[2].kind, ForceKind::Wind);
    expect_vec(p.forces[2].vector, 2.0, 0.0, 1.0);
    EXPECT_EQ(p.forces[2].strength, 0.3);
    EXPECT_EQ(p.forces[3].kind, ForceKind::Drag);
    EXPECT_EQ(p.forces[3].strength, 0.2);
    const ForceDesc& turb = p.forces[4];
    EXPECT_EQ(turb.kind, ForceKind::Turbulence);
    EXPECT_EQ(turb.strength, 1.5);
    EXPECT_EQ(turb.scale, 0.7);
    EXPECT_EQ(turb.speed, 0.4);
    EXPECT_EQ(turb.octaves, 3);
    EXPECT_EQ(turb.lacunarity, 2.5);
    EXPECT_EQ(turb.gain, 0.6);
    const ForceDesc& vortex = p.forces[5];
    EXPECT_EQ(vortex.kind, ForceKind::Vortex);
    EXPECT_EQ(vortex.strength, -2.0);
    expect_vec(vortex.center, 1.0, 0.0, 1.0);
    expect_vec(vortex.axis, 0.0, 1.0, 0.5);
    EXPECT_EQ(vortex.radius, 0.75);

    EXPECT_EQ(p.camera_path.kind, CameraPath::Kind::Keyframes);
    ASSERT_EQ(p.camera_path.keys.size(), 2u);
    EXPECT_EQ(p.camera_path.keys[1].time, 1.5);
    expect_vec(p.camera_path.keys[1].position, 2.0, 1.0, 5.0);
    expect_vec(p.camera_path.keys[1].look_at, 0.0, 1.5, 0.0);

    EXPECT_EQ(p.render.method, "reference");
    EXPECT_EQ(p.render.exposure, -1.5);
}

TEST(PresetFile, OrbitPath) {
    const Preset p = parse_preset_toml(
        "[camera_path]\ntype = \"orbit\"\ncenter = [1, 2, 3]\nradius = 4\nheight = -0.5\nstart_deg = 45\n"
        "deg_per_second = -12.5\n",
        "orbit.toml");
    EXPECT_EQ(p.camera_path.kind, CameraPath::Kind::Orbit);
    expect_vec(p.camera_path.orbit_center, 1.0, 2.0, 3.0);
    EXPECT_EQ(p.camera_path.orbit_radius, 4.0);
    EXPECT_EQ(p.camera_path.orbit_height, -0.5);
    EXPECT_EQ(p.camera_path.orbit_start_deg, 45.0);
    EXPECT_EQ(p.camera_path.orbit_deg_per_second, -12.5);
}

TEST(PresetFile, ANameFromTheFileStemMeetsTheNameRule) {
    // Frames are named NAME.0001.png: a stem the [preset] name rule would refuse is made to meet it, so a
    // file named .smoke.toml does not write hidden frames, nor "my smoke.toml" frames with a space.
    EXPECT_EQ(preset_name_from_file("dir/.smoke.toml"), "smoke");
    EXPECT_EQ(preset_name_from_file("..double.toml"), "double");
    EXPECT_EQ(preset_name_from_file("my smoke (v2).toml"), "my_smoke__v2_");
    EXPECT_EQ(preset_name_from_file("fog.v3.toml"), "fog.v3");
    EXPECT_EQ(preset_name_from_file("..toml"), "preset");
    EXPECT_EQ(preset_name_from_file("/dev/stdin"), "stdin");
    EXPECT_EQ(preset_name_from_file(std::string(300, 'a') + ".toml"), std::string(kMaxPresetName, 'a'));
    const Preset p = parse_preset_toml("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\nalbedo = [1, 1, 1]\n",
                                       "d/.hidden.toml");
    EXPECT_EQ(p.name, "hidden");
    // And every name made so is one the rule accepts when written back.
    for (const char* file : {"a b.toml", ".x.toml", "\xc3\xa9t\xc3\xa9.toml", "-.toml"}) {
        const std::string name = preset_name_from_file(file);
        EXPECT_NO_THROW(parse_preset_toml("[preset]\nname = \"" + name + "\"\n", "x.toml")) << name;
    }
}

TEST(PresetFile, AStaticSceneIsAPreset) {
    // No [timeline], no [[emitter]]: the defaults, and the name is the file's stem.
    const Preset p = parse_preset_toml("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\n"
                                       "albedo = [1, 1, 1]\n",
                                       "some/dir/still-life.toml");
    const Preset defaults;
    EXPECT_EQ(p.name, "still-life");
    EXPECT_EQ(p.description, "");
    EXPECT_EQ(p.scene.spheres.size(), 1u);
    EXPECT_TRUE(p.emitters.empty());
    EXPECT_TRUE(p.forces.empty());
    EXPECT_EQ(p.timeline.fps, defaults.timeline.fps);
    EXPECT_EQ(p.timeline.frame_count(), defaults.timeline.frame_count());
    EXPECT_EQ(p.camera_path.kind, CameraPath::Kind::Static);
    EXPECT_EQ(p.render.method, "auto");  // the fastest exact path on the device
    EXPECT_EQ(p.scene.camera.width, defaults.scene.camera.width);
    // The same text is a scene file too.
    expect_identical(parse_scene_toml("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nextinction = 1\n"
                                      "albedo = [1, 1, 1]\n",
                                      "x.toml"),
                     p.scene);
}

TEST(PresetFile, DensityEmitterDefaults) {
    const Preset p = parse_preset_toml("[[emitter]]\nshape = \"density\"\nfile = \"builtin:fog-sphere\"\n", "d.toml");
    ASSERT_EQ(p.emitters.size(), 1u);
    const EmitterDesc& e = p.emitters[0];
    const VolumeTransform identity;
    EXPECT_EQ(e.shape, EmitterShape::Density);
    EXPECT_EQ(e.density_source.file, "builtin:fog-sphere");
    EXPECT_EQ(e.density_source.grid, "density");
    EXPECT_TRUE(same(e.density_transform.translate, identity.translate));
    EXPECT_EQ(e.density_transform.scale, 1.0);
    EXPECT_TRUE(same(e.density_transform.rotate_deg, identity.rotate_deg));
    EXPECT_EQ(e.density, nullptr);
}

// --- Writing --------------------------------------------------------------------------------------

TEST(PresetFile, RoundTripIsExact) {
    const Preset original = parse_preset_toml(kEveryKey, "every.toml");
    const std::string text = preset_to_toml(original);
    expect_identical(parse_preset_toml(text, "written.toml"), original);
    EXPECT_NE(text.find("resolution = [400, 300]\n"), std::string::npos) << text;
    EXPECT_NE(text.find("[[vdb]]\nfile = \"grids/cloud.vdb\"\ngrid = \"smoke\"\n"), std::string::npos) << text;
    EXPECT_NE(text.find("max_spheres = 5000\n"), std::string::npos) << text;
    EXPECT_EQ(text.find("tolerance"), std::string::npos) << "max_spheres, not both: " << text;
    EXPECT_NE(text.find("shape = \"density\"\nfile = \"builtin:cloud:32\"\ngrid = \"density2\"\n"), std::string::npos)
        << text;
    EXPECT_NE(text.find("octaves = 3\n"), std::string::npos) << text;  // integers stay integers
}

TEST(PresetFile, RoundTripKeepsAwkwardValues) {
    Preset p;
    p.name = "awk";
    p.description = "quotes \" and \\ backslashes";
    p.timeline.fps = 1.0 / 3.0 * 100.0;
    p.timeline.duration = 0.1;
    p.timeline.seed = 0;
    EmitterDesc e;
    e.name = "tab\there";  // not one line: written escaped, rejected when read back (checked below)
    e.start = 1.0 / 7.0;
    e.speed = {-0.0, 0.0};  // -0.0 is not the same bits as 0.0: written as a pair
    e.lifetime = {0.30000000000000004, 0.30000000000000004};
    e.bursts = {{0.0, 0}, {5e-324, 10'000'000}};
    e.curves.albedo_ramp = {{0.0, {0.0, 0.25, 1.0}}, {1.0, {1.0, 1.0, 1.0}}};
    p.emitters.push_back(e);
    p.emitters[0].name = "plain";
    EmitterDesc d;
    d.name = "seeded";
    d.shape = EmitterShape::Density;
    d.center = {0.0, 0.0, 0.0};  // unused by the shape, so not written
    d.density_source = {"dir \"quoted\"\\cloud.vdb", "/base/not/written", "grid with spaces"};
    d.density_transform.translate = {-0.0, 1.0 / 3.0, -1e7};
    d.density_transform.scale = 5e-324;
    d.density_transform.rotate_deg = {-3600.0, 0.1, 2.0 / 3.0};
    p.emitters.push_back(d);
    VdbVolume v;
    v.source.file = "builtin:sheet:16";
    v.tolerance = 1.0 / 3.0;
    v.extinction_scale = 1e9;
    p.scene.volumes.push_back(v);
    ForceDesc f;
    f.kind = ForceKind::Turbulence;
    f.strength = 1e-300;
    f.octaves = 16;
    p.forces.push_back(f);
    p.camera_path.kind = CameraPath::Kind::Orbit;
    p.camera_path.orbit_start_deg = -0.1;
    const std::string text = preset_to_toml(p);
    expect_identical(parse_preset_toml(text, "awk.toml"), p);
    EXPECT_EQ(text.find("stop ="), std::string::npos) << "an emitter that never stops has no stop key";
    EXPECT_EQ(text.find("/base/not/written"), std::string::npos) << text;

    p.emitters[0].name = "tab\there";
    EXPECT_THROW(parse_preset_toml(preset_to_toml(p), "tab.toml"), SceneFileError);
}

// --- Rejections -----------------------------------------------------------------------------------

// The 1-based line of the first occurrence of `needle`.
int line_of(const std::string& text, const std::string& needle) {
    const std::size_t at = text.find(needle);
    if (at == std::string::npos) {
        ADD_FAILURE() << "no \"" << needle << "\" in\n" << text;
        return -1;
    }
    return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
}

// The message names the file, the line (that of `at`) and the key path, and says what is wrong.
void expect_rejected(const std::string& text, const std::string& at, const std::string& key_path,
                     const std::string& problem) {
    SCOPED_TRACE(text);
    const int line = line_of(text, at);
    try {
        parse_preset_toml(text, "preset.toml");
        ADD_FAILURE() << "accepted";
    } catch (const SceneFileError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.file(), "preset.toml");
        EXPECT_EQ(e.line(), line) << what;
        EXPECT_EQ(e.key_path(), key_path) << what;
        EXPECT_EQ(what.rfind("preset.toml:" + std::to_string(line) + ": " + key_path + ": ", 0), 0u) << what;
        EXPECT_NE(what.find(problem), std::string::npos) << what << "\n  should contain: " << problem;
    }
}

// A valid emitter with `line` added on its line 4.
std::string emitter(const std::string& line) { return "# an emitter\n[[emitter]]\nname = \"test\"\n" + line + "\n"; }
std::string curves(const std::string& lines) {
    return emitter("albedo = [0.8, 0.8, 0.8]") + "[emitter.curves]\n" + lines + "\n";
}
std::string force(const std::string& type, const std::string& lines) {
    return "[[force]]\ntype = \"" + type + "\"\n" + lines + "\n";
}

// Fire: an emitter's emission, times a ramp over age, reaches its spheres; written back and refused when bad.
TEST(PresetFile, EmitterEmissionAndItsRamp) {
    const std::string text = emitter("albedo = [0.2, 0.2, 0.2]\nemission = [8, 6, 3]") +
                             "[emitter.curves]\nemission_ramp = [{ age = 0, multiplier = [1, 1, 1] }, "
                             "{ age = 0.5, multiplier = [0.5, 0.25, 0.1] }, { age = 1, multiplier = [0, 0, 0] }]\n";
    const Preset p = parse_preset_toml(text, "fire.toml");
    ASSERT_EQ(p.emitters.size(), 1u);
    const EmitterDesc& e = p.emitters[0];
    expect_vec(e.emission, 8.0, 6.0, 3.0);
    ASSERT_EQ(e.curves.emission_ramp.size(), 3u);
    expect_vec(e.curves.emission_ramp[1].multiplier, 0.5, 0.25, 0.1);
    const AgeCurveFactors quarter = evaluate_age_curves(e.curves, 0.25);
    expect_vec(quarter.emission, 0.75, 0.625, 0.55);
    expect_vec(evaluate_age_curves(e.curves, 1.0).emission, 0.0, 0.0, 0.0);
    expect_vec(evaluate_age_curves(EmitterDesc{}.curves, 0.3).emission, 1.0, 1.0, 1.0);  // no ramp: 1
    expect_identical(parse_preset_toml(preset_to_toml(p), "written.toml"), p);
    // Without the keys nothing is written.
    const std::string plain = preset_to_toml(parse_preset_toml(emitter("albedo = [0.2, 0.2, 0.2]"), "plain.toml"));
    EXPECT_EQ(plain.find("emission"), std::string::npos) << plain;

    expect_rejected(emitter("emission = [1, -2, 0]"), "emission", "emitter[0].emission[1]",
                    "must not be negative (got -2)");
    expect_rejected(emitter("emission = [nan, 0, 0]"), "emission", "emitter[0].emission[0]", "must be finite");
    expect_rejected(curves("emission_ramp = [{ age = 0, multiplier = [1, -1, 1] }]"), "emission_ramp",
                    "emitter[0].curves.emission_ramp[0].multiplier[1]", "must not be negative (got -1)");
    expect_rejected(curves("emission_ramp = [{ age = 0.5, multiplier = [1, 1, 1] }, { age = 0.2, multiplier = [1, 1, "
                           "1] }]"),
                    "emission_ramp", "emitter[0].curves.emission_ramp[1].age", "must be greater than the previous");
    expect_rejected(curves("emission_ramp = [{ multiplier = [1, 1, 1] }]"), "emission_ramp",
                    "emitter[0].curves.emission_ramp[0].age", "missing (each emission_ramp key needs age and multiplier)");
    // An emission multiplier is not bounded by 1, as an albedo multiplier is.
    EXPECT_NO_THROW(parse_preset_toml(curves("emission_ramp = [{ age = 0, multiplier = [5, 5, 5] }]"), "ok.toml"));
}

TEST(PresetFileErrors, MessageReadsFileLineKeyProblem) {
    try {
        parse_preset_toml(emitter("rate = 1") + emitter("speed = [2, 1]"), "p.toml");
        FAIL() << "accepted";
    } catch (const SceneFileError& e) {
        EXPECT_STREQ(e.what(), "p.toml:8: emitter[1].speed: min must not exceed max (got [2, 1])");
    }
}

TEST(PresetFileErrors, UnknownKeysAndTables) {
    expect_rejected("[timelin]\nfps = 24\n", "[timelin]", "timelin", "unknown table (did you mean \"timeline\"?)");
    expect_rejected("[timeline]\nfsp = 24\n", "fsp", "timeline.fsp", "unknown key (did you mean \"fps\"?)");
    expect_rejected(emitter("rte = 3"), "rte", "emitter[0].rte", "did you mean \"rate\"?");
    expect_rejected(emitter("[emitter.curvs]\nfade_in = 0.1"), "[emitter.curvs]", "emitter[0].curvs",
                    "unknown table (did you mean \"curves\"?)");
    expect_rejected(curves("fade_inn = 0.1"), "fade_inn", "emitter[0].curves.fade_inn", "did you mean \"fade_in\"?");
    expect_rejected(emitter("bursts = [{ time = 1, count = 2, size = 3 }]"), "bursts", "emitter[0].bursts[0].size",
                    "unknown key");
    expect_rejected(force("drag", "strength = 1\nstrenght = 2"), "strenght", "force[0].strenght",
                    "did you mean \"strength\"?");
    expect_rejected("[render_settings]\nmethods = \"ppll\"\n", "methods", "render_settings.methods",
                    "did you mean \"method\"?");
    expect_rejected("[preset]\ntitle = \"x\"\n", "title", "preset.title", "allowed here: name, description");
    // In a preset the sections that make the scene move are homes too; a key that several read gets the list.
    expect_rejected("[timeline]\nexposure = 1\n", "exposure", "timeline.exposure",
                    "unknown key (it belongs under [render_settings]; allowed here: fps");
    expect_rejected("[camera]\nfps = 24\n", "fps", "camera.fps", "it belongs under [timeline];");
    expect_rejected("[timeline]\nradius = 1\n", "radius", "timeline.radius", "unknown key (allowed here: fps");
    expect_rejected("[[emitters]]\nrate = 1\n", "[[emitters]]", "emitters", "did you mean \"emitter\"?");
    // A section's key at the top level is pointed to its section.
    expect_rejected("fps = 24\n", "fps", "fps", "it belongs under [timeline]");
    expect_rejected("\ncone_deg = 5\n", "cone_deg", "cone_deg", "it belongs in an [[emitter]] section");
}

TEST(PresetFileErrors, KeysOfAnotherShapeOrType) {
    expect_rejected(force("gravity", "vector = [0, -9.8, 0]\nstrength = 2"), "strength", "force[0].strength",
                    "not used by type \"gravity\" (gravity takes vector)");
    expect_rejected(force("drag", "strength = 1\nscale = 2"), "scale", "force[0].scale",
                    "not used by type \"drag\" (drag takes strength)");
    expect_rejected(force("vortex", "strength = 1\noctaves = 2"), "octaves", "force[0].octaves",
                    "not used by type \"vortex\"");
    expect_rejected(emitter("radius = 0.5"), "radius", "emitter[0].radius",
                    "not used by shape \"point\" (it is for shape \"sphere\", \"disc\")");
    expect_rejected("[[emitter]]\nshape = \"sphere\"\nradius = 1\nhalf_extent = [1, 1, 1]\n", "half_extent",
                    "emitter[0].half_extent", "not used by shape \"sphere\"");
    expect_rejected("[camera_path]\ntype = \"static\"\nkeys = []\n", "keys", "camera_path.keys",
                    "not used by type \"static\" (it takes no other key)");
    expect_rejected("[camera_path]\ntype = \"orbit\"\nkeys = []\n", "keys", "camera_path.keys",
                    "not used by type \"orbit\" (orbit takes center, radius, height, start_deg, deg_per_second)");
}

TEST(PresetFileErrors, DensityEmitters) {
    const std::string head = "# a density emitter\n[[emitter]]\nshape = \"density\"\nfile = \"cloud.vdb\"\n";
    expect_rejected("[[emitter]]\nshape = \"density\"\ngrid = \"smoke\"\n", "[[emitter]]", "emitter[0].file",
                    "missing (a \"density\" emitter needs file: a .vdb path or builtin:NAME)");
    expect_rejected(head + "center = [0, 1, 0]\n", "center", "emitter[0].center",
                    "not used by shape \"density\" (it is for shape \"point\", \"sphere\", \"box\", \"disc\")");
    expect_rejected(head + "radius = 1\n", "radius", "emitter[0].radius",
                    "not used by shape \"density\" (it is for shape \"sphere\", \"disc\")");
    expect_rejected(head + "half_extent = [1, 1, 1]\n", "half_extent", "emitter[0].half_extent",
                    "not used by shape \"density\" (it is for shape \"box\")");
    expect_rejected(head + "normal = [0, 1, 0]\n", "normal", "emitter[0].normal", "not used by shape \"density\"");
    // ... and the density keys are not for the other shapes.
    expect_rejected(emitter("file = \"cloud.vdb\""), "file", "emitter[0].file",
                    "not used by shape \"point\" (it is for shape \"density\")");
    for (const char* key : {"grid = \"density\"", "translate = [0, 0, 0]", "scale = 1", "rotate = [0, 0, 0]"})
        expect_rejected("[[emitter]]\nshape = \"sphere\"\nradius = 1\n" + std::string(key) + "\n", key,
                        "emitter[0]." + std::string(key).substr(0, std::string(key).find(' ')),
                        "not used by shape \"sphere\" (it is for shape \"density\")");
    expect_rejected(head + "fiel = \"x.vdb\"\n", "fiel", "emitter[0].fiel", "unknown key (did you mean \"file\"?)");
    expect_rejected("[[emitter]]\nshape = \"density\"\nfile = \"\"\n", "file", "emitter[0].file", "must not be empty");
    expect_rejected("[[emitter]]\nshape = \"density\"\nfile = [\"a.vdb\"]\n", "file", "emitter[0].file",
                    "must be a string");
    expect_rejected(head + "grid = \"\"\n", "grid", "emitter[0].grid", "must not be empty");
    expect_rejected(head + "scale = 0\n", "scale", "emitter[0].scale", "scale must be positive, finite and at most");
    expect_rejected(head + "scale = -2\n", "scale", "emitter[0].scale", "(got -2)");
    expect_rejected(head + "translate = [0, -2e7, 0]\n", "translate", "emitter[0].translate",
                    "translate components must be finite");
    expect_rejected(head + "rotate = [0, nan, 0]\n", "rotate", "emitter[0].rotate[1]", "must be finite (got nan)");
    expect_rejected(head + "rotate = [0, 0, -3601]\n", "rotate", "emitter[0].rotate",
                    "rotate components must be finite degrees");
    // [[vdb]] keys that density emitters do not take.
    expect_rejected(head + "tolerance = 0.1\n", "tolerance", "emitter[0].tolerance", "unknown key");
    EXPECT_NO_THROW(parse_preset_toml(head + "grid = \"smoke\"\nscale = 3\nrate = 10\n", "ok.toml"));
}

TEST(PresetFileErrors, VdbTablesInPresets) {
    // The scene's [[vdb]] tables are read by the same code in presets (test_scene_file checks each rule).
    expect_rejected("[[vdb]]\nfile = \"a.vdb\"\ntolerance = 0.1\nmax_spheres = 10\n", "max_spheres",
                    "vdb[0].max_spheres", "give tolerance or max_spheres, not both");
    expect_rejected("[[vdb]]\nfile = \"a.vdb\"\nscael = 2\n", "scael", "vdb[0].scael", "did you mean \"scale\"?");
    expect_rejected("\ntolerance = 0.1\n", "tolerance", "tolerance", "it belongs in a [[vdb]] section");
}

TEST(PresetFileErrors, UnknownNames) {
    expect_rejected(emitter("shape = \"sphre\""), "sphre", "emitter[0].shape",
                    "must be one of \"point\", \"sphere\", \"box\", \"disc\", \"density\" (got \"sphre\"; did you mean "
                    "\"sphere\"?)");
    expect_rejected(force("gravty", "vector = [0, -1, 0]"), "gravty", "force[0].type",
                    "(got \"gravty\"; did you mean \"gravity\"?)");
    expect_rejected(force("magnetism", ""), "magnetism", "force[0].type",
                    "must be one of \"gravity\", \"buoyancy\", \"wind\", \"drag\", \"turbulence\", \"vortex\" "
                    "(got \"magnetism\")");
    expect_rejected("[camera_path]\ntype = \"orbitt\"\n", "orbitt", "camera_path.type", "did you mean \"orbit\"?");
    expect_rejected("[render_settings]\nmethod = \"sorted\"\n", "sorted", "render_settings.method",
                    "must be one of \"auto\", \"ppll\", \"tiles\", \"trace\", \"reference\" (got \"sorted\")");
}

TEST(PresetFileErrors, WrongTypes) {
    expect_rejected("[timeline]\nfps = \"fast\"\n", "fps", "timeline.fps", "must be a number (got a string \"fast\")");
    expect_rejected("[timeline]\nsubsteps = 2.5\n", "substeps", "timeline.substeps",
                    "must be an integer (got a floating-point number 2.5)");
    expect_rejected("[timeline]\nseed = true\n", "seed", "timeline.seed", "must be an integer");
    expect_rejected("[timeline]\nresolution = \"320x240\"\n", "resolution", "timeline.resolution",
                    "must be [width, height]");
    expect_rejected("[timeline]\nresolution = [320]\n", "resolution", "timeline.resolution", "must be [width, height]");
    expect_rejected(emitter("bursts = 5"), "bursts", "emitter[0].bursts", "must be an array of tables");
    expect_rejected(emitter("bursts = [1, 2]"), "bursts", "emitter[0].bursts[0]", "must be a table (got an integer 1)");
    expect_rejected(emitter("speed = \"quick\""), "quick", "emitter[0].speed", "must be a number or [min, max]");
    expect_rejected(emitter("speed = [1, 2, 3]"), "speed", "emitter[0].speed", "exactly 2 numbers (got 3)");
    expect_rejected(emitter("albedo = 0.5"), "albedo", "emitter[0].albedo",
                    "must be [r, g, b] or { min = [r, g, b], max = [r, g, b] }");
    expect_rejected("[[emitter]]\nname = 3\n", "name", "emitter[0].name", "must be a string (got an integer 3)");
    expect_rejected(emitter("curves = 1"), "curves", "emitter[0].curves", "must be a table");
    expect_rejected("timeline = 3\n", "timeline", "timeline", "must be a table");
    expect_rejected("[emitter]\nrate = 1\n", "[emitter]", "emitter", "write [[emitter]], not [emitter]");
    expect_rejected(force("wind", "vector = 1\nstrength = 1"), "vector", "force[0].vector",
                    "must be an array of 3 numbers");
}

TEST(PresetFileErrors, NanAndInf) {
    expect_rejected(emitter("rate = nan"), "rate = nan", "emitter[0].rate", "must be finite (got nan)");
    expect_rejected(emitter("stop = inf"), "stop", "emitter[0].stop", "must be finite (got inf)");
    expect_rejected(emitter("speed = [1, -inf]"), "speed", "emitter[0].speed[1]", "must be finite (got -inf)");
    expect_rejected("[timeline]\nduration = nan\n", "duration", "timeline.duration", "must be finite");
    expect_rejected(force("buoyancy", "strength = inf"), "strength", "force[0].strength", "must be finite");
    expect_rejected("[render_settings]\nexposure = -inf\n", "exposure", "render_settings.exposure", "must be finite");
    expect_rejected("[camera_path]\ntype = \"keyframes\"\nkeys = [\n  { time = 0, position = [0, 1, 5], look_at = "
                    "[0, 1, 0] },\n  { time = nan, position = [0, 1, 4], look_at = [0, 1, 0] },\n]\n",
                    "time = nan", "camera_path.keys[1].time", "must be finite");
}

TEST(PresetFileErrors, NegativeRatesRadiiLifetimes) {
    expect_rejected(emitter("rate = -1"), "rate = -1", "emitter[0].rate", "must not be negative (got -1)");
    expect_rejected(emitter("particle_radius = [-0.1, 0.2]"), "particle_radius", "emitter[0].particle_radius[0]",
                    "must be positive (got -0.1)");
    expect_rejected(emitter("particle_radius = 0"), "particle_radius", "emitter[0].particle_radius",
                    "must be positive (got 0)");
    expect_rejected(emitter("lifetime = -2"), "lifetime", "emitter[0].lifetime", "must be positive (got -2)");
    expect_rejected(emitter("lifetime = [0, 1]"), "lifetime", "emitter[0].lifetime[0]", "must be positive (got 0)");
    expect_rejected(emitter("extinction = [-1, 1]"), "extinction", "emitter[0].extinction[0]",
                    "must not be negative (got -1)");
    expect_rejected(emitter("speed = -1"), "speed", "emitter[0].speed", "must not be negative (got -1)");
    expect_rejected(emitter("jitter = -0.5"), "jitter", "emitter[0].jitter", "must not be negative");
    expect_rejected("[[emitter]]\nshape = \"disc\"\nradius = -1\n", "radius", "emitter[0].radius",
                    "must be positive (got -1)");
    expect_rejected("[[emitter]]\nshape = \"box\"\nhalf_extent = [1, -1, 1]\n", "half_extent",
                    "emitter[0].half_extent[1]", "must not be negative (got -1)");
    expect_rejected(curves("radius_growth = -1"), "radius_growth", "emitter[0].curves.radius_growth",
                    "must not be negative (got -1)");
    expect_rejected(force("drag", "strength = -0.1"), "strength", "force[0].strength", "must not be negative");
    expect_rejected(force("wind", "vector = [1, 0, 0]\nstrength = -1"), "strength", "force[0].strength",
                    "must not be negative");
    expect_rejected(force("vortex", "strength = 1\nradius = 0"), "radius = 0", "force[0].radius", "must be positive");
    expect_rejected(force("turbulence", "strength = 1\nscale = 0"), "scale", "force[0].scale", "must be positive");
    expect_rejected("[camera_path]\ntype = \"orbit\"\nradius = 0\n", "radius", "camera_path.radius",
                    "must be positive (got 0)");
    // Times are on the simulation clock, which starts at 0.
    expect_rejected(emitter("start = -1"), "start", "emitter[0].start", "must be in [0, 1e6] seconds (got -1)");
    expect_rejected(emitter("bursts = [{ time = -0.5, count = 1 }]"), "bursts", "emitter[0].bursts[0].time",
                    "must be in [0, 1e6] seconds");
}

TEST(PresetFileErrors, RangesAndOrder) {
    expect_rejected(emitter("speed = [2, 1]"), "speed", "emitter[0].speed", "min must not exceed max (got [2, 1])");
    expect_rejected(emitter("lifetime = [3, 2.5]"), "lifetime", "emitter[0].lifetime", "min must not exceed max");
    expect_rejected(emitter("albedo = { min = [0.5, 0.5, 0.5], max = [0.6, 0.4, 0.6] }"), "albedo",
                    "emitter[0].albedo.max[1]", "must not be below min (got max 0.4, min 0.5)");
    expect_rejected(emitter("albedo = { min = [0.5, 0.5, 0.5] }"), "albedo", "emitter[0].albedo.max",
                    "missing (albedo as a table needs min and max)");
    expect_rejected(emitter("albedo = [0.5, 1.2, 0.5]"), "albedo", "emitter[0].albedo[1]",
                    "must be in [0, 1] (got 1.2)");
    expect_rejected(emitter("start = 3\nstop = 2"), "stop", "emitter[0].stop",
                    "must not be before start (got stop 2, start 3)");
    expect_rejected(emitter("cone_deg = 181"), "cone_deg", "emitter[0].cone_deg",
                    "must be in [0, 180] degrees (got 181)");
    expect_rejected(curves("fade_in = 0.6\nfade_out = 0.5"), "fade_out", "emitter[0].curves.fade_out",
                    "fade_in + fade_out must not exceed 1 (got 0.6 + 0.5)");
    expect_rejected(curves("fade_out = 0.5\nfade_in = 0.6"), "fade_in", "emitter[0].curves.fade_in",
                    "must not exceed 1");
    expect_rejected(curves("fade_in = 1.5"), "fade_in", "emitter[0].curves.fade_in", "must be in [0, 1] (got 1.5)");
    expect_rejected(
        curves("albedo_ramp = [{ age = 0, multiplier = [1, 1, 1] },\n  { age = 1.5, multiplier = [1, 1, 1] }]"),
        "age = 1.5", "emitter[0].curves.albedo_ramp[1].age", "must be in [0, 1] (got 1.5)");
    expect_rejected(curves("albedo_ramp = [{ age = -0.1, multiplier = [1, 1, 1] }]"), "albedo_ramp",
                    "emitter[0].curves.albedo_ramp[0].age", "must be in [0, 1] (got -0.1)");
    expect_rejected(curves("albedo_ramp = [\n  { age = 0.5, multiplier = [1, 1, 1] },\n  { age = 0.5, multiplier = "
                           "[1, 1, 1] },\n]"),
                    "age = 0.5, multiplier = [1, 1, 1] },\n]", "emitter[0].curves.albedo_ramp[1].age",
                    "must be greater than the previous key's age (got 0.5 after 0.5)");
    expect_rejected(curves("albedo_ramp = [{ age = 0 }]"), "albedo_ramp", "emitter[0].curves.albedo_ramp[0].multiplier",
                    "missing (each albedo_ramp key needs age and multiplier)");
    // The multiplied albedo must stay an albedo (emitter albedo 0.8 here).
    expect_rejected(curves("albedo_ramp = [{ age = 0, multiplier = [1, 1.5, 1] }]"), "albedo_ramp",
                    "emitter[0].curves.albedo_ramp[0].multiplier[1]",
                    "makes the albedo exceed 1 (albedo max 0.8 * 1.5");
    EXPECT_NO_THROW(
        parse_preset_toml(curves("albedo_ramp = [{ age = 0, multiplier = [1.25, 1.25, 1.25] }]"), "ok.toml"));
}

TEST(PresetFileErrors, TimelineLimits) {
    expect_rejected("[timeline]\nfps = 0\n", "fps", "timeline.fps", "must be in (0, 240] frames per second (got 0)");
    expect_rejected("[timeline]\nfps = 241\n", "fps", "timeline.fps", "must be in (0, 240]");
    expect_rejected("[timeline]\nduration = 0\n", "duration", "timeline.duration",
                    "must be in (0, 3600] seconds (got 0)");
    expect_rejected("[timeline]\nduration = 3600.5\n", "duration", "timeline.duration", "(got 3600.5)");
    expect_rejected("[timeline]\nsubsteps = 0\n", "substeps", "timeline.substeps", "must be between 1 and 64 (got 0)");
    expect_rejected("[timeline]\nsubsteps = 65\n", "substeps", "timeline.substeps",
                    "must be between 1 and 64 (got 65)");
    expect_rejected("[timeline]\npreroll = -1\n", "preroll", "timeline.preroll", "must be in [0, 3600] seconds");
    expect_rejected("[timeline]\nmax_particles = 0\n", "max_particles", "timeline.max_particles",
                    "must be between 1 and 10000000 (got 0)");
    expect_rejected("[timeline]\nmax_particles = 10000001\n", "max_particles", "timeline.max_particles",
                    "must be between 1 and 10000000 (got 10000001)");
    expect_rejected("[timeline]\nseed = -1\n", "seed", "timeline.seed", "(got -1)");
    expect_rejected("[timeline]\nresolution = [0, 240]\n", "resolution", "timeline.resolution[0]",
                    "must be between 1 and 16384 (got 0)");
    expect_rejected("[timeline]\nfps = 1\nduration = 0.25\n", "duration", "timeline.duration",
                    "duration * fps gives no frame (got 0.25 s at 1 fps)");
    EXPECT_NO_THROW(parse_preset_toml(
        "[timeline]\nfps = 240\nduration = 3600\nsubsteps = 64\nmax_particles = 10000000\n", "ok.toml"));
}

TEST(PresetFileErrors, BurstCounts) {
    expect_rejected(emitter("bursts = [{ time = 1, count = 10000001 }]"), "bursts", "emitter[0].bursts[0].count",
                    "must be between 0 and 10000000 (got 10000001)");
    expect_rejected(emitter("bursts = [{ time = 1, count = -5 }]"), "bursts", "emitter[0].bursts[0].count",
                    "(got -5)");
    expect_rejected(emitter("bursts = [{ time = 1, count = 2.0 }]"), "bursts", "emitter[0].bursts[0].count",
                    "must be an integer");
    expect_rejected(emitter("bursts = [{ count = 2 }]"), "bursts", "emitter[0].bursts[0].time",
                    "missing (each burst needs time and count)");
}

TEST(PresetFileErrors, AbsurdMagnitudes) {
    expect_rejected(emitter("center = [0, 1e8, 0]"), "center", "emitter[0].center[1]", "absurd size");
    expect_rejected(emitter("rate = 1e8"), "rate = 1e8", "emitter[0].rate",
                    "absurd size: must be at most 1e7 (got 1e+08)");
    expect_rejected(emitter("speed = [1, 2e6]"), "speed", "emitter[0].speed[1]", "absurd size");
    expect_rejected(emitter("extinction = 1e10"), "extinction", "emitter[0].extinction", "absurd size");
    expect_rejected(force("gravity", "vector = [0, -1e7, 0]"), "vector", "force[0].vector[1]", "absurd size");
    expect_rejected(force("buoyancy", "strength = -2e6"), "strength", "force[0].strength", "absurd size");
    expect_rejected(force("turbulence", "strength = 1\noctaves = 17"), "octaves", "force[0].octaves",
                    "must be between 1 and 16");
    expect_rejected("[render_settings]\nexposure = 100\n", "exposure", "render_settings.exposure",
                    "must be in [-64, 64] stops (got 100)");
}

TEST(PresetFileErrors, DirectionsMustNotBeZero) {
    expect_rejected(emitter("direction = [0, 0, 0]"), "direction", "emitter[0].direction", "must not be zero");
    expect_rejected("[[emitter]]\nshape = \"disc\"\nradius = 1\nnormal = [0, 0, 0]\n", "normal", "emitter[0].normal",
                    "must not be zero");
    expect_rejected(force("vortex", "strength = 1\naxis = [0, 0, 0]"), "axis", "force[0].axis", "must not be zero");
}

TEST(PresetFileErrors, MissingKeys) {
    expect_rejected("\n[[force]]\nstrength = 1\n", "[[force]]", "force[0].type", "missing (each [[force]] needs type");
    expect_rejected(force("gravity", ""), "[[force]]", "force[0].vector", "missing (a \"gravity\" force needs vector)");
    expect_rejected(force("wind", "vector = [1, 0, 0]"), "[[force]]", "force[0].strength",
                    "missing (a \"wind\" force needs vector, strength)");
    expect_rejected(force("turbulence", "scale = 1"), "[[force]]", "force[0].strength", "missing");
    expect_rejected("[[emitter]]\nshape = \"disc\"\n", "[[emitter]]", "emitter[0].radius",
                    "missing (a \"disc\" emitter needs radius)");
    expect_rejected("[[emitter]]\nshape = \"box\"\n", "[[emitter]]", "emitter[0].half_extent",
                    "missing (a \"box\" emitter needs half_extent)");
    expect_rejected("[camera_path]\nradius = 3\n", "[camera_path]", "camera_path.type", "missing");
    expect_rejected("[camera_path]\ntype = \"keyframes\"\n", "[camera_path]", "camera_path.keys", "missing");
}

TEST(PresetFileErrors, CameraKeyframes) {
    const std::string head = "[camera_path]\ntype = \"keyframes\"\n";
    expect_rejected(head + "keys = [{ time = 0, position = [0, 1, 5], look_at = [0, 1, 0] }]\n", "keys",
                    "camera_path.keys", "needs at least 2 keys (got 1)");
    expect_rejected(head + "keys = [\n  { time = 1, position = [0, 1, 5], look_at = [0, 1, 0] },\n"
                           "  { time = 1, position = [0, 1, 4], look_at = [0, 1, 0] },\n]\n",
                    "time = 1, position = [0, 1, 4]", "camera_path.keys[1].time",
                    "must be later than the previous key's time (got 1 after 1)");
    expect_rejected(head + "keys = [\n  { time = 0, position = [0, 1, 5], look_at = [0, 1, 5] },\n"
                           "  { time = 1, position = [0, 1, 4], look_at = [0, 1, 0] },\n]\n",
                    "time = 0", "camera_path.keys[0].look_at", "must differ from position");
    expect_rejected(head + "keys = [\n  { time = 0, position = [0, 1, 5], look_at = [0, 1, 0] },\n"
                           "  { time = 1, position = [0, 5, 0], look_at = [0, 1, 0] },\n]\n",
                    "time = 1", "camera_path.keys[1].look_at", "must not be parallel to camera.up");
    expect_rejected(head +
                        "keys = [\n  { time = 0, position = [0, 1, 5] },\n  { time = 1, position = [0, 1, 4], "
                        "look_at = [0, 1, 0] },\n]\n",
                    "time = 0", "camera_path.keys[0].look_at",
                    "missing (each camera key needs time, position, look_at)");
}

TEST(PresetFileErrors, PresetNameAndDescription) {
    expect_rejected("[preset]\nname = \"a/b\"\n", "name", "preset.name", "it names output files; got \"a/b\"");
    expect_rejected("[preset]\nname = \"\"\n", "name", "preset.name", "letters, digits");
    expect_rejected("[preset]\nname = \".hidden\"\n", "name", "preset.name", "not starting with '.'");
    expect_rejected("[preset]\ndescription = \"two\\nlines\"\n", "description", "preset.description",
                    "must be one line");
    expect_rejected("[preset]\ndescription = \"\"\"\nmulti\nline\"\"\"\n", "description", "preset.description",
                    "must be one line");
}

TEST(PresetFileErrors, SceneFilesHoldNoPresetSections) {
    for (const char* section : {"preset", "timeline", "camera_path", "render_settings"}) {
        const std::string text = std::string("[camera]\nwidth = 64\n\n[") + section + "]\n";
        try {
            parse_scene_toml(text, "scene.toml");
            ADD_FAILURE() << "a scene file accepted [" << section << "]";
        } catch (const SceneFileError& e) {
            EXPECT_EQ(e.line(), 4) << e.what();
            EXPECT_EQ(e.key_path(), section);
            EXPECT_NE(std::string(e.what()).find("a preset section: not allowed in a static scene file"),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(parse_scene_toml(emitter(""), "scene.toml"), SceneFileError);
    EXPECT_THROW(parse_scene_toml(force("drag", "strength = 1"), "scene.toml"), SceneFileError);
}

TEST(PresetFileErrors, MalformedToml) {
    try {
        parse_preset_toml("[timeline]\nfps = = 3\n", "bad.toml");
        FAIL() << "accepted";
    } catch (const SceneFileError& e) {
        EXPECT_EQ(e.line(), 2) << e.what();
        EXPECT_NE(std::string(e.what()).find("invalid TOML"), std::string::npos) << e.what();
    }
}

// --- Shipped presets ------------------------------------------------------------------------------

TEST(ShippedPresets, AreTheFilesInPresetsExceptTheDefaultScene) {
    std::set<std::string> on_disk;
    for (const auto& entry : fs::directory_iterator(kPresetDir))
        if (entry.path().extension() == ".toml" && entry.path().filename() != "default.toml")
            on_disk.insert(entry.path().stem().string());
    const std::vector<std::string> names = builtin_preset_names();
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), on_disk);
    for (const std::string& name : kShipped) EXPECT_TRUE(on_disk.count(name)) << name << " is not shipped";
    EXPECT_FALSE(builtin_preset("default").has_value()) << "default.toml is the static default scene, not a preset";
    EXPECT_FALSE(builtin_preset("no-such-preset").has_value());
}

TEST(ShippedPresets, EmbeddedTextMatchesTheFiles) {
    // A stale copy would mean the build missed an edit.
    for (const std::string& name : builtin_preset_names()) {
        const std::optional<std::string_view> text = builtin_preset_toml(name);
        ASSERT_TRUE(text.has_value()) << name;
        EXPECT_EQ(*text, file_text(kPresetDir / (name + ".toml"))) << name;
    }
}

TEST(ShippedPresets, ParseAndRoundTrip) {
    for (const std::string& name : builtin_preset_names()) {
        SCOPED_TRACE(name);
        const std::optional<Preset> p = builtin_preset(name);
        ASSERT_TRUE(p.has_value());
        EXPECT_EQ(p->name, name);
        EXPECT_EQ(p->scene.source, "built-in preset " + name);
        EXPECT_FALSE(p->description.empty());
        expect_identical(parse_preset_toml(preset_to_toml(*p), "written.toml"), *p);
        // The file on disk reads the same (and names itself in messages).
        expect_identical(load_preset_file(kPresetDir / (name + ".toml")), *p);
    }
}

TEST(ShippedPresets, AreCheapEnoughForCi) {
    for (const std::string& name : builtin_preset_names()) {
        SCOPED_TRACE(name);
        const Preset p = *builtin_preset(name);
        EXPECT_EQ(p.timeline.fps, 24.0);
        EXPECT_LE(p.timeline.duration, 10.0);
        // Exact: the fastest exact path on the device; layers keeps the paper's method on the paper's scene.
        EXPECT_EQ(p.render.method, name == "layers" ? "ppll" : "auto");
        if (name == "layers") continue;  // the benchmark's own size, and no particles
        EXPECT_LE(p.timeline.max_particles, 5000u);
        EXPECT_EQ(p.scene.camera.width, 320);
        EXPECT_EQ(p.scene.camera.height, 240);
        EXPECT_FALSE(p.emitters.empty());
    }
}

TEST(ShippedPresets, ShowWhatTheirNamesSay) {
    const auto has_force = [](const Preset& p, ForceKind k) {
        return std::any_of(p.forces.begin(), p.forces.end(), [k](const ForceDesc& f) { return f.kind == k; });
    };
    const Preset plume = *builtin_preset("plume");
    EXPECT_TRUE(has_force(plume, ForceKind::Buoyancy) && has_force(plume, ForceKind::Wind));

    const Preset fog = *builtin_preset("ground-fog");
    EXPECT_GE(fog.scene.boxes.size(), 3u) << "fog drifting around boxes";
    EXPECT_EQ(fog.camera_path.kind, CameraPath::Kind::Orbit);

    const Preset campfire = *builtin_preset("campfire");
    EXPECT_TRUE(std::any_of(campfire.emitters.begin(), campfire.emitters.end(),
                            [](const EmitterDesc& e) { return e.bursts.size() >= 2; }));

    const Preset explosion = *builtin_preset("explosion");
    for (const EmitterDesc& e : explosion.emitters) {
        EXPECT_EQ(e.rate, 0.0) << "bursts only";
        EXPECT_FALSE(e.bursts.empty());
    }

    // The fog bank's camera flies through the bank: at some frame the eye is inside the emitter's box.
    const Preset bank = *builtin_preset("fog-bank");
    ASSERT_EQ(bank.camera_path.kind, CameraPath::Kind::Keyframes);
    ASSERT_EQ(bank.emitters.size(), 1u);
    const EmitterDesc& e = bank.emitters[0];
    ASSERT_EQ(e.shape, EmitterShape::Box);
    int frames_inside = 0;
    for (int f = 0; f < bank.timeline.frame_count(); ++f) {
        const glm::dvec3 eye = camera_at(bank, bank.timeline.preroll + f / bank.timeline.fps).position;
        const glm::dvec3 d = glm::abs(eye - e.center);
        frames_inside += d.x < e.half_extent.x && d.y < e.half_extent.y && d.z < e.half_extent.z;
    }
    EXPECT_GT(frames_inside, bank.timeline.frame_count() / 4);
    EXPECT_LT(frames_inside, bank.timeline.frame_count()) << "it should also be seen from outside";

    // Two streams aimed at each other, slightly offset, seen by a static camera.
    const Preset crossing = *builtin_preset("crossing");
    EXPECT_EQ(crossing.camera_path.kind, CameraPath::Kind::Static);
    ASSERT_EQ(crossing.emitters.size(), 2u);
    const EmitterDesc &a = crossing.emitters[0], &b = crossing.emitters[1];
    const glm::dvec3 gap = b.center - a.center;
    EXPECT_GT(glm::dot(a.direction, gap), 0.0);
    EXPECT_LT(glm::dot(b.direction, gap), 0.0);
    const double offset = glm::length(glm::cross(gap, glm::normalize(a.direction)));
    EXPECT_GT(offset, 0.0) << "offset, not head on";
    EXPECT_LT(offset, a.radius_range.max + b.radius_range.max) << "close enough to interpenetrate";
}

// Light through the smoke (docs/accuracy.md): every preset but the benchmark scene `layers` (whose 16
// full-screen layers are bench layers' geometry and light) has shadows; those with a ground shade it by
// the sun and the smoke's shadows; the fires burn: emission over age that ends in soot.
TEST(ShippedPresets, AreLitAndBurn) {
    for (const std::string& name : builtin_preset_names()) {
        if (name == "layers") continue;
        SCOPED_TRACE(name);
        const Preset p = *builtin_preset(name);
        EXPECT_TRUE(p.scene.lighting.shadows);
        if (name == "vdb-cloud") continue;  // a cloud in the sky: no ground
        ASSERT_FALSE(p.scene.boxes.empty());
        EXPECT_GT(glm::length(p.scene.boxes[0].diffuse), 0.0) << "the ground is lit";
        EXPECT_EQ(p.scene.boxes[0].radiance, glm::dvec3(0.0));
    }
    for (const char* name : {"campfire", "explosion"}) {
        SCOPED_TRACE(name);
        const Preset p = *builtin_preset(name);
        const auto fire = std::find_if(p.emitters.begin(), p.emitters.end(),
                                       [](const EmitterDesc& e) { return glm::length(e.emission) > 0.0; });
        ASSERT_NE(fire, p.emitters.end());
        // White-yellow when young (red >= green >= blue), nothing left at the end of the ramp.
        const AgeCurveFactors young = evaluate_age_curves(fire->curves, 0.0);
        const glm::dvec3 e0 = fire->emission * young.emission;
        EXPECT_TRUE(e0.r >= e0.g && e0.g >= e0.b && e0.b > 0.0);
        EXPECT_EQ(evaluate_age_curves(fire->curves, 1.0).emission, glm::dvec3(0.0));
    }
}

// No world edge: a preset's ground (its first box, top face y = 0) reaches so far that, from every
// camera position of its timeline, its nearest edge lies less than one pixel below the horizon at the
// preset's resolution. (A 30-unit ground showed its far edge as a line across the view.)
TEST(ShippedPresets, GroundEdgeStaysWithinAPixelOfTheHorizon) {
    int grounds = 0;
    for (const std::string& name : builtin_preset_names()) {
        SCOPED_TRACE(name);
        const Preset p = *builtin_preset(name);
        if (p.scene.boxes.empty()) continue;  // layers, vdb-cloud: nothing stands on a ground
        ++grounds;
        const Box& ground = p.scene.boxes[0];
        ASSERT_EQ(ground.max.y, 0.0);
        const double pixel_rad = p.scene.camera.fov_y_deg * std::acos(-1.0) / 180.0 / double(p.scene.camera.height);
        const int frames = p.timeline.frame_count();
        for (int f = 0; f <= frames; f += std::max(1, frames / 16)) {
            const Camera cam = camera_at(p, p.timeline.preroll + f / p.timeline.fps);
            const glm::dvec3 eye = cam.position;
            ASSERT_GT(eye.y, 0.0);
            const double to_edge = std::min({eye.x - ground.min.x, ground.max.x - eye.x, eye.z - ground.min.z,
                                              ground.max.z - eye.z});
            ASSERT_GT(to_edge, 0.0);
            EXPECT_LT(std::atan(eye.y / to_edge), pixel_rad) << "frame " << f << ": the ground's edge is visible";
        }
    }
    EXPECT_GE(grounds, 6);
}

TEST(ShippedPresets, LayersIsTheBenchmarkScene) {
    const Preset p = *builtin_preset("layers");
    const Scene bench = make_layers_scene(16, 800, 600);
    EXPECT_TRUE(p.emitters.empty());
    EXPECT_EQ(p.camera_path.kind, CameraPath::Kind::Static);
    EXPECT_EQ(p.scene.camera.width, 800);
    EXPECT_EQ(p.scene.camera.height, 600);
    EXPECT_EQ(p.scene.camera.position, bench.camera.position);
    EXPECT_EQ(p.scene.camera.look_at, bench.camera.look_at);
    EXPECT_EQ(p.scene.camera.fov_y_deg, bench.camera.fov_y_deg);
    EXPECT_EQ(p.scene.render.min_transmittance, 0.0);
    EXPECT_TRUE(p.scene.boxes.empty());
    ASSERT_EQ(p.scene.spheres.size(), bench.spheres.size());
    // The file holds the decimals; the code computes them in binary.
    for (std::size_t i = 0; i < bench.spheres.size(); ++i) {
        const Sphere &s = p.scene.spheres[i], &t = bench.spheres[i];
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(s.center[c], t.center[c], 1e-12) << "sphere " << i;
            EXPECT_NEAR(s.albedo[c], t.albedo[c], 1e-12) << "sphere " << i;
        }
        EXPECT_NEAR(s.radius, t.radius, 1e-12) << "sphere " << i;
        EXPECT_EQ(s.extinction, t.extinction) << "sphere " << i;
    }
}

TEST(ShippedPresets, DefaultIsPlume) {
    EXPECT_EQ(default_preset_name(), "plume");
    const std::vector<std::string> names = builtin_preset_names();
    EXPECT_NE(std::find(names.begin(), names.end(), default_preset_name()), names.end());
}

// --- Resolving names and paths --------------------------------------------------------------------

class PresetOnDisk : public testing::ScratchDir {};

TEST_F(PresetOnDisk, ResolvesBuiltInNames) {
    const Preset p = resolve_preset("crossing");
    EXPECT_EQ(p.name, "crossing");
    EXPECT_EQ(p.scene.source, "built-in preset crossing");
}

TEST_F(PresetOnDisk, ResolvesPaths) {
    const fs::path path = dir_ / "mine.toml";
    std::ofstream(path) << kEveryKey;
    const Preset p = resolve_preset(path.string());
    EXPECT_EQ(p.name, "every-key");
    EXPECT_EQ(p.scene.source, path.string());
    expect_identical(p, load_preset_file(path));

    // Without [preset] name, the stem names it; a file shadows a built-in of the same name.
    const fs::path plume = dir_ / "plume";
    std::ofstream(plume) << "[timeline]\nfps = 12\n";
    const Preset q = resolve_preset(plume.string());
    EXPECT_EQ(q.name, "plume");
    EXPECT_EQ(q.timeline.fps, 12.0);
}

TEST_F(PresetOnDisk, ADirectoryDoesNotShadowABuiltIn) {
    // `brume play plume` writes ./plume/; playing it again must still find the built-in.
    const fs::path previous = fs::current_path();
    fs::create_directories(dir_ / "plume");
    fs::current_path(dir_);
    Preset p;
    EXPECT_NO_THROW(p = resolve_preset("plume"));
    fs::current_path(previous);
    EXPECT_EQ(p.scene.source, "built-in preset plume");
}

TEST_F(PresetOnDisk, UnknownNameListsTheBuiltIns) {
    try {
        resolve_preset("plum");
        FAIL() << "resolved an unknown name";
    } catch (const SceneFileError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.file(), "plum");
        EXPECT_NE(what.find("not a built-in preset (did you mean \"plume\"?)"), std::string::npos) << what;
        std::string list;
        for (const std::string& n : builtin_preset_names()) list += (list.empty() ? "" : ", ") + n;
        EXPECT_NE(what.find("built-in presets: " + list), std::string::npos) << what;
    }
    EXPECT_THROW(resolve_preset((dir_ / "missing.toml").string()), SceneFileError);
}

TEST_F(PresetOnDisk, GridFilesAreFoundBesideThePreset) {
    fs::create_directories(dir_ / "presets" / "grids");
    std::ofstream(dir_ / "presets" / "grids" / "plume.vdb") << "stand-in bytes";
    const fs::path path = dir_ / "presets" / "seeded.toml";
    std::ofstream(path) << "[[vdb]]\nfile = \"grids/plume.vdb\"\n\n[[emitter]]\nshape = \"sphere\"\nradius = 1\n\n"
                           "[[emitter]]\nshape = \"density\"\nfile = \"grids/plume.vdb\"\n";
    const std::string dir = (dir_ / "presets").string();
    for (const Preset& p : {load_preset_file(path), resolve_preset(path.string())}) {
        ASSERT_EQ(p.scene.volumes.size(), 1u);
        ASSERT_EQ(p.emitters.size(), 2u);
        EXPECT_EQ(p.scene.volumes[0].source.base_dir, dir);
        EXPECT_EQ(p.emitters[1].density_source.base_dir, dir);
        EXPECT_EQ(p.emitters[0].density_source.base_dir, "") << "not a density emitter";
        EXPECT_TRUE(fs::exists(fs::path(p.emitters[1].density_source.base_dir) / p.emitters[1].density_source.file));
    }
    // A relative preset path gives a relative base_dir, right from the working directory it was given in.
    const fs::path previous = fs::current_path();
    fs::current_path(dir_);
    Preset relative;
    EXPECT_NO_THROW(relative = load_preset_file("presets/seeded.toml"));
    const bool found = fs::exists(fs::path(relative.emitters.at(1).density_source.base_dir) / "grids/plume.vdb");
    fs::current_path(previous);
    EXPECT_EQ(relative.emitters[1].density_source.base_dir, "presets");
    EXPECT_TRUE(found);
    // Text parsed without a file, as the built-in presets are, reads grids from the working directory.
    const Preset text = parse_preset_toml(file_text(path), "seeded.toml");
    EXPECT_EQ(text.scene.volumes[0].source.base_dir, "");
    EXPECT_EQ(text.emitters[1].density_source.base_dir, "");
    for (const std::string& name : builtin_preset_names()) {
        const Preset b = *builtin_preset(name);
        for (const VdbVolume& v : b.scene.volumes) EXPECT_EQ(v.source.base_dir, "") << name;
        for (const EmitterDesc& e : b.emitters) EXPECT_EQ(e.density_source.base_dir, "") << name;
    }
}

TEST_F(PresetOnDisk, ErrorsNameTheFile) {
    const fs::path path = dir_ / "bad.toml";
    std::ofstream(path) << emitter("rate = -3");
    try {
        load_preset_file(path);
        FAIL() << "accepted a negative rate";
    } catch (const SceneFileError& e) {
        EXPECT_EQ(std::string(e.what()), path.string() + ":4: emitter[0].rate: must not be negative (got -3)");
    }
    try {
        load_preset_file(dir_ / "absent.toml");
        FAIL() << "loaded a missing file";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace brume
