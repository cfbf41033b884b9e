// Scene files (the format README.md describes): TOML in, validated Scene out, and Scene back to TOML.
// Everything a renderer could choke on (unknown keys, wrong types, NaN/Inf, negative or absurd sizes)
// is rejected with the file, line and key, so no renderer has to re-check its input. The sections are
// read by sim/scene_sections.h, which the preset reader (sim/preset_file.h) reuses for a preset's scene.
#pragma once

#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace brume {

// Beyond these a scene is rejected as absurd rather than rendered slowly or wrongly.
inline constexpr std::size_t kMaxSpheres = 50'000'000;
inline constexpr std::size_t kMaxBoxes = 100'000;
inline constexpr std::size_t kMaxVolumes = 10'000;  // [[vdb]] tables
inline constexpr int kMaxImageSide = 16384;         // camera.width and camera.height
inline constexpr double kMaxCoordinate = 1e7;       // |any coordinate|, any radius
inline constexpr double kMaxExtinction = 1e9;       // sphere.extinction
inline constexpr double kMaxRadiance = 1e9;         // any radiance, ambient or sun component
inline constexpr double kMaxFovYDeg = 179.0;
inline constexpr int kMaxSupersample = 8;          // camera.supersample: k x k rays per pixel

// what() reads "scene.toml:12: sphere[3].radius: must be positive and finite (got -1)".
// Array indices in key paths count from 0, in file order. line/column are 0 when unknown.
class SceneFileError : public std::runtime_error {
public:
    SceneFileError(std::string file, int line, int column, std::string key_path, std::string problem);

    const std::string& file() const { return file_; }
    int line() const { return line_; }
    int column() const { return column_; }
    const std::string& key_path() const { return key_path_; }  // empty for syntax and I/O errors
    const std::string& problem() const { return problem_; }

private:
    std::string file_;
    int line_;
    int column_;
    std::string key_path_;
    std::string problem_;
};

// Parses and validates a scene; source_name stands for the file in messages and becomes Scene::source.
// A preset section ([timeline], [[emitter]], ...) is an error here: presets are read by sim/preset_file.h.
// [[vdb]] tables are recorded, not read: their base_dir is left empty (the working directory).
Scene parse_scene_toml(std::string_view text, const std::string& source_name);

// Reads and parses a file; a missing or unreadable file is a SceneFileError naming it and the OS reason.
// Every volume's base_dir is the file's directory (path.parent_path(), as given), so a relative [[vdb]]
// file is found beside the scene wherever it is run from.
Scene load_scene_file(const std::filesystem::path& path);

// Writes every field in the schema parse_scene_toml reads. Numbers are printed as the shortest text that
// reads back to the same double, so parse_scene_toml(scene_to_toml(s)) reproduces s exactly (bar source
// and the volumes' base_dir: a [[vdb]] file is written as given).
// No validation: a scene with NaN or negative radii is written as is and rejected when read back.
std::string scene_to_toml(const Scene& scene);

// Text helpers shared by the scene and preset readers and writers.
namespace toml_text {

// Shortest text that reads back to the same double: "1", "0.1", "nan", "-inf" (for messages).
std::string shortest(double v);
// As shortest, but always a TOML float ("1.0", not "1"), so written files keep their types.
void append_float(std::string& out, double v);
// `key = [x, y, z]` and `key = v`, each on its own line, as TOML floats.
void append_vec3(std::string& out, std::string_view key, const glm::dvec3& v);
void append_number(std::string& out, std::string_view key, double v);
// The entry of `known` closest to `unknown` within two edits (typos, transpositions): did-you-mean.
std::optional<std::string_view> suggest(std::string_view unknown, std::span<const std::string_view> known);
// A TOML basic string, quoted and escaped so that it stays on one line.
std::string quoted(std::string_view s);
// Text from a file as a message echoes it: at most `limit` bytes (cut at a UTF-8 character boundary),
// then "... (N bytes)", so an 8 MB key or value never makes an 8 MB error line.
std::string excerpt(std::string_view s, std::size_t limit = 64);
// The whole file; a missing or unreadable file is a SceneFileError naming it and the OS reason.
std::string read_file(const std::filesystem::path& path);
// The folder a file's relative paths ([[vdb]] files, density emitters' grids) are found from: the
// file's own, or for a stream (standard input, a pipe, anything under /dev or /proc), which has none,
// the working directory ("").
std::string relative_base(const std::filesystem::path& path);
// A density grid's `file` and `grid` keys (base_dir is not written: it is where the file is read from),
// and its placement's translate, scale and rotate: shared by [[vdb]] and density emitters.
void append_density_source(std::string& out, const DensitySource& source);
void append_volume_transform(std::string& out, const VolumeTransform& transform);
// The [camera], [lighting], [render], [[box]], [[sphere]] and [[vdb]] sections, as scene_to_toml writes them.
void append_scene_sections(std::string& out, const Scene& scene);

}  // namespace toml_text

}  // namespace brume
