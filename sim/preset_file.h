// Preset files: the scene file format (sim/scene_file.h) plus the sections that make a scene move,
// read into a validated Preset and written back exactly. The preset reader builds on the scene reader:
// it reads the scene sections with the scene's own code (sim/scene_sections.h) and its own sections
// with sim/preset_sections.h, so the scene format does not depend on this one.
//
// Schema (every section optional; [[...]] may repeat; a range is [min, max] or one number):
//   [preset]          name (default: the file's stem; letters, digits, - _ .), description (one line)
//   [timeline]        fps, duration, substeps, preroll, seed, max_particles, resolution = [w, h]
//                     (resolution overrides [camera] width and height)
//   [camera] [lighting] [render] [[box]] [[sphere]]     as in a scene file
//   [[vdb]]           a density grid converted to static spheres (sim/scene.h VdbVolume), also in scene
//                     files: file (required: a .vdb path, relative to this file's directory, or
//                     "builtin:NAME[:RESOLUTION]"), grid (default "density"), albedo_grid (default:
//                     the file's "albedo" grid if it has one; "" for none),
//                     extinction_scale (> 0), albedo (a number or [r, g, b], in [0, 1]), tolerance (in
//                     (0, 1]) or max_spheres (1 to kMaxSpheres), both only with fit = true (bool), and the placement
//                     translate = [x, y, z], scale, rotate = [x, y, z] (degrees about x, then y, then z)
//   [[emitter]]       name, shape = "point"|"sphere"|"box"|"disc"|"density", center (all but density),
//                     radius (sphere, disc), half_extent (box), normal (disc), file, grid, translate,
//                     scale, rotate (density: births follow the grid's trilinear field, the keys as in
//                     [[vdb]]), rate, start, stop, bursts = [{ time, count }],
//                     direction, speed, cone_deg, jitter, lifetime, particle_radius, extinction,
//                     albedo = [r, g, b] or { min = [r, g, b], max = [r, g, b] }, emission = [r, g, b]
//   [emitter.curves]  radius_growth, fade_in, fade_out, albedo_ramp = [{ age, multiplier = [r, g, b] }],
//                     emission_ramp (as albedo_ramp, multiplying emission)
//   [[force]]         type = "gravity" (vector) | "buoyancy" (strength) | "wind" (vector, strength)
//                     | "drag" (strength) | "turbulence" (strength; scale, speed, octaves, lacunarity,
//                     gain) | "vortex" (strength; center, axis, radius)
//   [camera_path]     type = "static" | "keyframes" (keys = [{ time, position, look_at }], 2 or more)
//                     | "orbit" (center, radius, height, start_deg, deg_per_second)
//   [render_settings] method = "auto"|"ppll"|"tiles"|"trace"|"reference", exposure (stops)
// A key another shape or type uses is an error, as is an unknown one. Times (start, stop, bursts,
// camera keys) are seconds on the simulation clock (sim/simulator.h), which starts at 0 and includes
// the preroll. Errors are SceneFileErrors: "plume.toml:31: emitter[0].speed: min must not exceed max
// (got [2, 1])".
#pragma once

#include "sim/preset.h"
#include "sim/scene_file.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace brume {

// Beyond these a preset is rejected as absurd rather than simulated slowly or wrongly.
inline constexpr double kMaxFps = 240.0;
inline constexpr double kMaxDurationSeconds = 3600.0;  // also the bound on preroll
inline constexpr int kMaxSubsteps = 64;
inline constexpr std::uint32_t kMaxParticles = 10'000'000;
// [preset] name: NAME.####.png and its hidden temporary ".NAME.####.png.tmp-XXXXXXXX" must fit in a
// file name (255 bytes); 100 leaves room, and a longer name is no name a person types.
inline constexpr std::size_t kMaxPresetName = 100;
// The characters a preset's name may hold: it names output files (NAME.0001.png), so no paths and no
// shell-hostile characters; a name also must not start with '.' (hidden frames).
inline constexpr bool is_preset_name_character(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
           c == '.';
}
// The name of a preset that sets none, from its file's stem: held to the rule a written name meets
// (leading dots dropped, other characters '_', at most kMaxPresetName), "preset" when nothing is left.
std::string preset_name_from_file(const std::filesystem::path& file);
inline constexpr std::uint32_t kMaxBurstCount = 10'000'000;
inline constexpr double kMaxEmissionRate = 10'000'000.0;  // particles per second
inline constexpr double kMaxTimeSeconds = 1e6;             // emission windows, bursts, camera keys (>= 0)
inline constexpr double kMaxForce = 1e6;                   // accelerations, velocities, strengths
inline constexpr double kMaxExposureStops = 64.0;
inline constexpr std::size_t kMaxEmitters = 10'000;
inline constexpr std::size_t kMaxForces = 10'000;
inline constexpr std::size_t kMaxListEntries = 1'000'000;  // bursts, ramp keys, camera keys

// Parses and validates a preset; source_name stands for the file in messages, becomes scene.source,
// and its stem is the name unless [preset] sets one (preset_name_from_file). Grid files are not opened (base_dir stays empty and
// density emitters' samplers null: sim/vdb/volume_loader.h prepare_preset reads them).
Preset parse_preset_toml(std::string_view text, const std::string& source_name);

// Reads and parses a file; a missing or unreadable file is a SceneFileError naming it and the OS reason.
// The base_dir of every [[vdb]] volume and density emitter is the file's directory, as in load_scene_file.
Preset load_preset_file(const std::filesystem::path& path);

// A document that may be either, told apart by its sections: one with any section only a preset reads
// ([preset], [timeline], [[emitter]], [[force]], [camera_path], [render_settings]) is read as a preset,
// any other as a scene (load_scene_file's rules, base_dir included). The file is read once, so it may be
// a stream (standard input). Exactly one of the two is set.
struct SceneOrPreset {
    std::optional<Scene> scene;
    std::optional<Preset> preset;
};
SceneOrPreset load_scene_or_preset_file(const std::filesystem::path& path);

// Writes every field parse_preset_toml reads, numbers as their shortest exact text, so that
// parse_preset_toml(preset_to_toml(p)) reproduces p (bar scene.source). The camera's width and height
// are also written as [timeline] resolution; fields the emitter's shape, force's type or path's type
// does not use are left out (they read back as defaults), as is base_dir and the density sampler.
// No validation, as for scene_to_toml.
std::string preset_to_toml(const Preset& preset);

}  // namespace brume
