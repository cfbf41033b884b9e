// Scene files' entry points (sim/scene_file.h), their error type, the text helpers the scene and preset
// readers and writers share (toml_text) and the scene writer. Reading is the scene sections' reader
// (sim/scene_sections.h) on a document that holds nothing else.
#include "sim/scene_file.h"

#include "sim/scene_sections.h"
#include "sim/toml_reader.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <memory>
#include <system_error>
#include <utility>
#include <vector>

namespace brume {

namespace {

std::string format_message(const std::string& file, int line, int column, const std::string& key_path,
                           const std::string& problem) {
    std::string m = file;
    if (line > 0) {
        m += ':' + std::to_string(line);
        if (column > 0) m += ':' + std::to_string(column);
    }
    m += ": ";
    if (!key_path.empty()) m += key_path + ": ";
    m += problem;
    return m;
}

}  // namespace

SceneFileError::SceneFileError(std::string file, int line, int column, std::string key_path, std::string problem)
    : std::runtime_error(format_message(file, line, column, key_path, problem)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_path_(std::move(key_path)),
      problem_(std::move(problem)) {}

namespace toml_text {

// std::to_chars guarantees the round trip.
std::string shortest(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

void append_float(std::string& out, double v) {
    const std::size_t start = out.size();
    out += shortest(v);
    if (out.find_first_of(".en", start) == std::string::npos) out += ".0";  // 'n': nan, inf
}

void append_vec3(std::string& out, std::string_view key, const glm::dvec3& v) {
    out += key;
    out += " = [";
    for (int c = 0; c < 3; ++c) {
        if (c) out += ", ";
        append_float(out, v[c]);
    }
    out += "]\n";
}

void append_number(std::string& out, std::string_view key, double v) {
    out += key;
    out += " = ";
    append_float(out, v);
    out += '\n';
}

namespace {

// Optimal string alignment distance (Levenshtein plus adjacent transpositions): "raduis" is 1 from "radius".
std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[a.size()][b.size()];
}

}  // namespace

std::optional<std::string_view> suggest(std::string_view unknown, std::span<const std::string_view> known) {
    std::optional<std::string_view> best;
    std::size_t best_distance = 3;  // suggest only within distance 2
    for (const std::string_view k : known) {
        // The distance is at least the difference in length: a huge key costs nothing here (it
        // once cost a matrix of its length times the name's, 1.4 GB for an 8 MB key).
        if (unknown.size() > k.size() + 2 || k.size() > unknown.size() + 2) continue;
        const std::size_t dist = edit_distance(unknown, k);
        if (dist < best_distance) {
            best = k;
            best_distance = dist;
        }
    }
    return best;
}

std::string excerpt(std::string_view s, std::size_t limit) {
    if (s.size() <= limit) return std::string(s);
    std::size_t cut = limit;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xc0) == 0x80) --cut;  // not inside a character
    return std::string(s.substr(0, cut)) + "... (" + std::to_string(s.size()) + " bytes)";
}

// Text from a file is printed quoted and escaped, so a message stays one readable line.
std::string quoted(std::string_view s) {
    std::string q = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            q += '\\';
            q += c;
        } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            q += buf;
        } else {
            q += c;
        }
    }
    return q + '"';
}

std::string relative_base(const std::filesystem::path& path) {
    // /dev/stdin and its kin name a descriptor, not a folder, even where the shell gave them a file.
    const std::string text = path.string();
    if (text.starts_with("/dev/") || text.starts_with("/proc/")) return "";
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec) ? path.parent_path().string() : std::string();
}

std::string read_file(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw SceneFileError(name, 0, 0, "", "cannot read: is a directory");
    // A device (/dev/zero, /dev/urandom) never ends: refused by name, before any read. Pipes and
    // FIFOs are read, up to a bound no scene file comes near.
    if (std::filesystem::is_character_file(path, ec) || std::filesystem::is_block_file(path, ec))
        throw SceneFileError(name, 0, 0, "", "cannot read: is a device, not a scene file");
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) {
        const int err = errno;
        throw SceneFileError(name, 0, 0, "", "cannot open: " + std::generic_category().message(err));
    }
    std::string text;
    char buf[1 << 16];
    std::size_t got = 0;
    constexpr std::size_t kMaxSceneBytes = std::size_t(1) << 30;
    while ((got = std::fread(buf, 1, sizeof buf, f.get())) > 0) {
        text.append(buf, got);
        if (text.size() > kMaxSceneBytes)
            throw SceneFileError(name, 0, 0, "", "cannot read: longer than 1 GiB, not a scene file");
    }
    if (std::ferror(f.get())) {
        const int err = errno;
        throw SceneFileError(name, 0, 0, "", "cannot read: " + std::generic_category().message(err));
    }
    return text;
}

void append_density_source(std::string& out, const DensitySource& source) {
    out += "file = " + toml_text::quoted(source.file) + '\n';
    out += "grid = " + toml_text::quoted(source.grid) + '\n';
}

void append_volume_transform(std::string& out, const VolumeTransform& transform) {
    append_vec3(out, "translate", transform.translate);
    append_number(out, "scale", transform.scale);
    append_vec3(out, "rotate", transform.rotate_deg);
}

void append_scene_sections(std::string& out, const Scene& scene) {
    out.reserve(out.size() + 1024 + scene.boxes.size() * 128 + scene.spheres.size() * 160);
    const Camera& c = scene.camera;
    out += "\n[camera]\n";
    if (!scene.frame_volumes) {  // else the volume loader places it
        append_vec3(out, "position", c.position);
        append_vec3(out, "look_at", c.look_at);
    }
    append_vec3(out, "up", c.up);
    append_number(out, "fov_y_deg", c.fov_y_deg);
    out += "width = " + std::to_string(c.width) + '\n';
    out += "height = " + std::to_string(c.height) + '\n';
    // The light keys are written only where they differ from their defaults, so a scene without them
    // reads back as the same text it always did.
    if (c.supersample != 1) out += "supersample = " + std::to_string(c.supersample) + '\n';

    const Lighting& l = scene.lighting;
    out += "\n[lighting]\n";
    append_vec3(out, "ambient", l.ambient);
    append_vec3(out, "sun", l.sun);
    append_vec3(out, "sun_direction", l.sun_direction);
    append_vec3(out, "background", l.background);
    if (l.shadows) out += "shadows = true\n";

    out += "\n[render]\n";
    append_number(out, "min_transmittance", scene.render.min_transmittance);
    if (scene.render.shadow_technique != ShadowTechnique::Accurate)
        out += std::string("shadow_technique = \"") + kShadowTechniqueNames[int(scene.render.shadow_technique)] + "\"\n";

    for (const Box& b : scene.boxes) {
        out += "\n[[box]]\n";
        append_vec3(out, "min", b.min);
        append_vec3(out, "max", b.max);
        append_vec3(out, "radiance", b.radiance);
        if (b.diffuse != glm::dvec3(0.0)) append_vec3(out, "diffuse", b.diffuse);
    }
    for (const Sphere& s : scene.spheres) {
        out += "\n[[sphere]]\n";
        append_vec3(out, "center", s.center);
        append_number(out, "radius", s.radius);
        append_number(out, "extinction", s.extinction);
        append_vec3(out, "albedo", s.albedo);
        if (s.emission != glm::dvec3(0.0)) append_vec3(out, "emission", s.emission);
    }
    for (const VdbVolume& v : scene.volumes) {
        out += "\n[[vdb]]\n";
        append_density_source(out, v.source);
        if (v.albedo_grid) out += "albedo_grid = " + toml_text::quoted(*v.albedo_grid) + '\n';
        append_number(out, "extinction_scale", v.extinction_scale);
        append_vec3(out, "albedo", v.albedo);
        // One or the other for a tiling (the reader refuses both); a fit has its tolerance and maybe a cap.
        if (v.fit) out += "fit = true\n";
        if (v.max_spheres == 0 || v.fit) append_number(out, "tolerance", v.tolerance);
        if (v.max_spheres > 0) out += "max_spheres = " + std::to_string(v.max_spheres) + '\n';
        append_volume_transform(out, v.transform);
    }
}

}  // namespace toml_text

Scene parse_scene_toml(std::string_view text, const std::string& source_name) {
    return read_scene(toml_read::Reader(text, source_name), source_name);
}

Scene load_scene_file(const std::filesystem::path& path) {
    Scene scene = parse_scene_toml(toml_text::read_file(path), path.string());
    const std::string dir = toml_text::relative_base(path);
    for (VdbVolume& v : scene.volumes) v.source.base_dir = dir;
    return scene;
}

std::string scene_to_toml(const Scene& scene) {
    std::string out = "# Brume scene (schema: sim/scene_file.h)\n";
    toml_text::append_scene_sections(out, scene);
    return out;
}

}  // namespace brume
