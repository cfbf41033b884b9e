// Writing presets: preset_to_toml (declared in sim/preset_file.h) and the writers of the sections only
// presets hold, apart from the readers so that each file holds one direction. The scene sections are
// written by toml_text::append_scene_sections (sim/scene_file.h), exactly as scene_to_toml writes them.
#include "sim/preset_file.h"

#include "sim/preset_sections.h"

#include <cmath>
#include <string>
#include <string_view>

namespace brume {

namespace {

using toml_text::append_float;
using toml_text::append_number;
using toml_text::append_vec3;

bool same_bits(double a, double b) { return a == b && std::signbit(a) == std::signbit(b); }

void append_inline_vec3(std::string& out, const glm::dvec3& v) {
    out += '[';
    for (int c = 0; c < 3; ++c) {
        if (c) out += ", ";
        append_float(out, v[c]);
    }
    out += ']';
}

// One number when the range is a constant, [min, max] otherwise.
void append_range(std::string& out, std::string_view key, const Range& r) {
    out += key;
    out += " = ";
    if (same_bits(r.min, r.max)) {
        append_float(out, r.min);
    } else {
        out += '[';
        append_float(out, r.min);
        out += ", ";
        append_float(out, r.max);
        out += ']';
    }
    out += '\n';
}

void append_string(std::string& out, std::string_view key, std::string_view value) {
    out += key;
    out += " = " + toml_text::quoted(value) + '\n';
}

void append_emitter(std::string& out, const EmitterDesc& e) {
    out += "\n[[emitter]]\n";
    append_string(out, "name", e.name);
    append_string(out, "shape", kShapeNames[std::size_t(e.shape)]);
    if (e.shape != EmitterShape::Density) append_vec3(out, "center", e.center);
    if (e.shape == EmitterShape::Sphere || e.shape == EmitterShape::Disc) append_number(out, "radius", e.radius);
    if (e.shape == EmitterShape::Box) append_vec3(out, "half_extent", e.half_extent);
    if (e.shape == EmitterShape::Disc) append_vec3(out, "normal", e.normal);
    if (e.shape == EmitterShape::Density) {
        toml_text::append_density_source(out, e.density_source);
        toml_text::append_volume_transform(out, e.density_transform);
    }
    append_number(out, "rate", e.rate);
    append_number(out, "start", e.start);
    if (!(std::isinf(e.stop) && e.stop > 0)) append_number(out, "stop", e.stop);  // absent: never stops
    out += "bursts = [";
    for (std::size_t i = 0; i < e.bursts.size(); ++i) {
        out += i ? ", " : "";
        out += "{ time = ";
        append_float(out, e.bursts[i].time);
        out += ", count = " + std::to_string(e.bursts[i].count) + " }";
    }
    out += "]\n";
    append_vec3(out, "direction", e.direction);
    append_range(out, "speed", e.speed);
    append_number(out, "cone_deg", e.cone_deg);
    append_number(out, "jitter", e.jitter);
    append_range(out, "lifetime", e.lifetime);
    append_range(out, "particle_radius", e.radius_range);
    append_range(out, "extinction", e.extinction);
    out += "albedo = { min = ";
    append_inline_vec3(out, e.albedo.min);
    out += ", max = ";
    append_inline_vec3(out, e.albedo.max);
    out += " }\n";
    if (e.emission != glm::dvec3(0.0)) append_vec3(out, "emission", e.emission);  // absent: none

    const AgeCurves& c = e.curves;
    out += "[emitter.curves]\n";
    append_number(out, "radius_growth", c.radius_growth);
    append_number(out, "fade_in", c.fade_in);
    append_number(out, "fade_out", c.fade_out);
    out += "albedo_ramp = [";
    for (std::size_t i = 0; i < c.albedo_ramp.size(); ++i) {
        out += i ? ",\n  " : "\n  ";
        out += "{ age = ";
        append_float(out, c.albedo_ramp[i].age);
        out += ", multiplier = ";
        append_inline_vec3(out, c.albedo_ramp[i].multiplier);
        out += " }";
    }
    out += c.albedo_ramp.empty() ? "]\n" : ",\n]\n";
    if (!c.emission_ramp.empty()) {
        out += "emission_ramp = [";
        for (const AgeCurves::AlbedoKey& k : c.emission_ramp) {
            out += "\n  { age = ";
            append_float(out, k.age);
            out += ", multiplier = ";
            append_inline_vec3(out, k.multiplier);
            out += " },";
        }
        out += "\n]\n";
    }
}

void append_force(std::string& out, const ForceDesc& f) {
    out += "\n[[force]]\n";
    append_string(out, "type", kForceNames[std::size_t(f.kind)]);
    for (const std::string_view k : force_keys(f.kind)) {
        if (k == "vector") append_vec3(out, k, f.vector);
        else if (k == "strength") append_number(out, k, f.strength);
        else if (k == "scale") append_number(out, k, f.scale);
        else if (k == "speed") append_number(out, k, f.speed);
        else if (k == "octaves") out += "octaves = " + std::to_string(f.octaves) + '\n';
        else if (k == "lacunarity") append_number(out, k, f.lacunarity);
        else if (k == "gain") append_number(out, k, f.gain);
        else if (k == "center") append_vec3(out, k, f.center);
        else if (k == "axis") append_vec3(out, k, f.axis);
        else if (k == "radius") append_number(out, k, f.radius);
    }
}

void append_camera_path(std::string& out, const CameraPath& cp) {
    out += "\n[camera_path]\n";
    append_string(out, "type", kCameraPathNames[std::size_t(cp.kind)]);
    if (cp.kind == CameraPath::Kind::Keyframes) {
        out += "keys = [";
        for (const CameraKey& k : cp.keys) {
            out += "\n  { time = ";
            append_float(out, k.time);
            out += ", position = ";
            append_inline_vec3(out, k.position);
            out += ", look_at = ";
            append_inline_vec3(out, k.look_at);
            out += " },";
        }
        out += cp.keys.empty() ? "]\n" : "\n]\n";
    } else if (cp.kind == CameraPath::Kind::Orbit) {
        append_vec3(out, "center", cp.orbit_center);
        append_number(out, "radius", cp.orbit_radius);
        append_number(out, "height", cp.orbit_height);
        append_number(out, "start_deg", cp.orbit_start_deg);
        append_number(out, "deg_per_second", cp.orbit_deg_per_second);
    }
}

}  // namespace

std::string preset_to_toml(const Preset& p) {
    std::string out = "# Brume preset (schema: sim/preset_file.h)\n\n[preset]\n";
    append_string(out, "name", p.name);
    append_string(out, "description", p.description);

    const Timeline& tl = p.timeline;
    out += "\n[timeline]\n";
    append_number(out, "fps", tl.fps);
    append_number(out, "duration", tl.duration);
    out += "substeps = " + std::to_string(tl.substeps) + '\n';
    append_number(out, "preroll", tl.preroll);
    out += "seed = " + std::to_string(tl.seed) + '\n';
    out += "max_particles = " + std::to_string(tl.max_particles) + '\n';
    out +=
        "resolution = [" + std::to_string(p.scene.camera.width) + ", " + std::to_string(p.scene.camera.height) + "]\n";

    toml_text::append_scene_sections(out, p.scene);
    for (const EmitterDesc& e : p.emitters) append_emitter(out, e);
    for (const ForceDesc& f : p.forces) append_force(out, f);
    append_camera_path(out, p.camera_path);

    out += "\n[render_settings]\n";
    append_string(out, "method", p.render.method);
    append_number(out, "exposure", p.render.exposure);
    return out;
}

}  // namespace brume
