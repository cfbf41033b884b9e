// The preset sections' schema and readers (sim/preset_sections.h): one function per section, each checking
// its keys and values with the toolkit (sim/toml_reader.h) and the limits of sim/preset_file.h.
#include "sim/preset_sections.h"

#include "sim/camera_rays.h"
#include "sim/preset_file.h"
#include "sim/scene_sections.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace brume {

using toml_read::contains;
using toml_read::join;
using toml_read::KeyPath;
using toml_read::last_of;
using toml_read::Reader;
using toml_read::Vec3Field;
using toml_text::shortest;

namespace {

// Every table a preset's top level holds, in the order messages list them.
constexpr std::array<std::string_view, 12> kPresetRootKeys{
    "preset", "timeline", "camera", "lighting", "render", "box", "sphere", "vdb", "emitter", "force", "camera_path",
    "render_settings"};

// kPresetRootKeys is the scene's sections and the preset's, each once: a section added to either list
// must be added there too.
constexpr bool lists_each_section_once(std::span<const std::string_view> names) {
    std::size_t found = 0;
    for (const std::string_view s : kSceneSections) found += std::count(names.begin(), names.end(), s) == 1;
    for (const std::string_view s : kPresetSections) found += std::count(names.begin(), names.end(), s) == 1;
    return found == names.size() && found == kSceneSections.size() + kPresetSections.size();
}
static_assert(lists_each_section_once(kPresetRootKeys));

// The schema, in the order keys are checked and written.
constexpr std::array<std::string_view, 2> kPresetKeys{"name", "description"};
constexpr std::array<std::string_view, 7> kTimelineKeys{"fps",  "duration",      "substeps",  "preroll",
                                                        "seed", "max_particles", "resolution"};
constexpr std::array<std::string_view, 25> kEmitterKeys{
    "name",      "shape",    "center", "radius",   "half_extent",     "normal",     "file",   "grid",
    "translate", "scale",    "rotate", "rate",     "start",           "stop",       "bursts", "direction",
    "speed",     "cone_deg", "jitter", "lifetime", "particle_radius", "extinction", "albedo", "emission",
    "curves"};
constexpr std::array<std::string_view, 2> kBurstKeys{"time", "count"};
constexpr std::array<std::string_view, 5> kCurveKeys{"radius_growth", "fade_in", "fade_out", "albedo_ramp",
                                                     "emission_ramp"};
constexpr std::array<std::string_view, 2> kRampKeys{"age", "multiplier"};
constexpr std::array<std::string_view, 2> kColorRangeKeys{"min", "max"};
constexpr std::array<std::string_view, 11> kForceKeys{"type",   "vector",     "strength", "scale",
                                                      "speed",  "octaves",    "lacunarity", "gain",
                                                      "center", "axis",       "radius"};
constexpr std::array<std::string_view, 7> kCameraPathKeys{"type",   "keys",      "center",        "radius",
                                                          "height", "start_deg", "deg_per_second"};
constexpr std::array<std::string_view, 3> kCameraKeyKeys{"time", "position", "look_at"};
constexpr std::array<std::string_view, 2> kRenderSettingsKeys{"method", "exposure"};

// The exact methods (render/methods/registry.cpp): a preset renders the model, never an approximation of it.
constexpr std::array<std::string_view, 5> kMethodNames{"auto", "ppll", "tiles", "trace", "reference"};

// The keys each emitter shape, force type and camera path type reads, beside the ones all share.
constexpr std::array<std::string_view, 0> kNoKeys{};
// A density emitter is placed by its transform, so center belongs to the other shapes only.
constexpr std::array<std::string_view, 1> kPointShapeKeys{"center"};
constexpr std::array<std::string_view, 2> kSphereShapeKeys{"center", "radius"};
constexpr std::array<std::string_view, 2> kBoxShapeKeys{"center", "half_extent"};
constexpr std::array<std::string_view, 3> kDiscShapeKeys{"center", "radius", "normal"};
constexpr std::array<std::string_view, 5> kDensityShapeKeys{"file", "grid", "translate", "scale", "rotate"};
constexpr std::array<std::string_view, 1> kGravityKeys{"vector"};
constexpr std::array<std::string_view, 1> kStrengthKey{"strength"};
constexpr std::array<std::string_view, 2> kWindKeys{"vector", "strength"};
constexpr std::array<std::string_view, 6> kTurbulenceKeys{"strength", "scale",      "speed",
                                                          "octaves",  "lacunarity", "gain"};
constexpr std::array<std::string_view, 4> kVortexKeys{"strength", "center", "axis", "radius"};
constexpr std::array<std::string_view, 1> kKeyframesKeys{"keys"};
constexpr std::array<std::string_view, 5> kOrbitKeys{"center", "radius", "height", "start_deg", "deg_per_second"};

// Where a key misplaced at the top level belongs, looked for after the scene's sections.
const std::array<toml_read::SectionHint, 6> kPresetSectionHints{{
    {kPresetKeys, "it belongs under [preset]"},
    {kTimelineKeys, "it belongs under [timeline]"},
    {kEmitterKeys, "it belongs in an [[emitter]] section"},
    {kForceKeys, "it belongs in a [[force]] section"},
    {kCameraPathKeys, "it belongs under [camera_path]"},
    {kRenderSettingsKeys, "it belongs under [render_settings]"},
}};

std::span<const std::string_view> shape_keys(EmitterShape s) {
    switch (s) {
        case EmitterShape::Point: return kPointShapeKeys;
        case EmitterShape::Sphere: return kSphereShapeKeys;
        case EmitterShape::Box: return kBoxShapeKeys;
        case EmitterShape::Disc: return kDiscShapeKeys;
        case EmitterShape::Density: return kDensityShapeKeys;
    }
    return kNoKeys;
}

std::span<const std::string_view> camera_path_keys(CameraPath::Kind k) {
    switch (k) {
        case CameraPath::Kind::Static: return kNoKeys;
        case CameraPath::Kind::Keyframes: return kKeyframesKeys;
        case CameraPath::Kind::Orbit: return kOrbitKeys;
    }
    return kNoKeys;
}

// --- Values only presets hold ---------------------------------------------------------------------

// Seconds since the start of the simulation, preroll included.
double sim_time(const Reader& in, const toml::node& n, const KeyPath& path) {
    return in.in_interval(n, path, 0.0, kMaxTimeSeconds, false, " seconds");
}

// An acceleration or velocity.
glm::dvec3 force_vector(const Reader& in, const toml::node& n, const KeyPath& path) {
    const Vec3Field f = in.vec3(n, path);
    in.each(f, path, [](double v) { return std::abs(v) <= kMaxForce; }, "absurd size: must be within 1e6 of 0");
    return f.v;
}

// `[min, max]` or one number for both; `element` reads and checks each bound.
template <class Element>
Range range(const Reader& in, const toml::node& n, const KeyPath& path, Element element) {
    if (n.is_integer() || n.is_floating_point()) {
        const double v = element(n, path);
        return {v, v};
    }
    const toml::array* a = n.as_array();
    if (!a) in.fail(n, path, "must be a number or [min, max] (got " + toml_read::describe(n) + ")");
    if (a->size() != 2)
        in.fail(n, path, "must be [min, max], an array of exactly 2 numbers (got " + std::to_string(a->size()) + ")");
    const Range r{element((*a)[0], path[0]), element((*a)[1], path[1])};
    if (!(r.min <= r.max))
        in.fail(n, path, "min must not exceed max (got [" + shortest(r.min) + ", " + shortest(r.max) + "])");
    return r;
}

// `[r, g, b]` for a constant, or `{ min = [r, g, b], max = [r, g, b] }`.
ColorRange color_range(const Reader& in, const toml::node& n, const KeyPath& path) {
    if (n.is_array()) {
        const glm::dvec3 c = in.albedo(n, path).v;
        return {c, c};
    }
    const toml::table* t = n.as_table();
    if (!t)
        in.fail(n, path,
                "must be [r, g, b] or { min = [r, g, b], max = [r, g, b] } (got " + toml_read::describe(n) + ")");
    in.check_keys(*t, path, kColorRangeKeys);
    const std::string_view needs = "albedo as a table needs min and max";
    const KeyPath min_path = path / "min";
    const KeyPath max_path = path / "max";
    const Vec3Field lo = in.albedo(in.required(*t, "min", path, needs), min_path);
    const Vec3Field hi = in.albedo(in.required(*t, "max", path, needs), max_path);
    for (std::size_t c = 0; c < 3; ++c) {
        const int i = static_cast<int>(c);
        if (!(lo.v[i] <= hi.v[i]))
            in.fail(*hi.elems[c], max_path[c],
                    "must not be below min (got max " + shortest(hi.v[i]) + ", min " + shortest(lo.v[i]) + ")");
    }
    return {lo.v, hi.v};
}

// The view direction must be defined and not parallel to up (make_camera_rays normalises both).
void check_view(const Reader& in, const toml::source_region& at, const KeyPath& path, const glm::dvec3& position,
                const glm::dvec3& look_at, const glm::dvec3& up, const char* same_point) {
    const glm::dvec3 view = look_at - position;
    const double view_length = glm::length(view);
    if (!(view_length > 0.0)) in.fail(at, path, same_point);
    const double up_length = glm::length(up);
    if (up_length > 0.0 && !view_has_roll(view, up))
        in.fail(at, path, "the view direction (look_at - position) must not be parallel to camera.up");
}

// --- Sections -------------------------------------------------------------------------------------

void read_preset(const Reader& in, const toml::node& node, const KeyPath& path, Preset& p) {
    const toml::table& t = in.table(node, path, kPresetKeys);
    if (const toml::node* n = t.get("name")) {
        const KeyPath np = path / "name";
        p.name = in.one_line(*n, np);
        // The name names output files (`brume play` writes NAME.0001.png): no paths, no hidden files.
        const bool ok = !p.name.empty() && p.name[0] != '.' && std::ranges::all_of(p.name, is_preset_name_character);
        if (!ok)
            in.fail(*n, np,
                    "must be letters, digits, '-', '_' and '.', not starting with '.' (it names output files; got " +
                        toml_text::quoted(toml_text::excerpt(p.name)) + ")");
        // NAME.####.png and its hidden temporary must fit a file name (255 bytes) wherever the file moves.
        if (p.name.size() > kMaxPresetName)
            in.fail(*n, np,
                    "must be at most " + std::to_string(kMaxPresetName) + " characters (it names output files; got " +
                        std::to_string(p.name.size()) + ")");
    }
    if (const toml::node* n = t.get("description")) p.description = in.one_line(*n, path / "description");
}

void read_timeline(const Reader& in, const toml::node& node, const KeyPath& path, Timeline& tl, Camera& camera) {
    const toml::table& t = in.table(node, path, kTimelineKeys);
    const toml::node* fps = t.get("fps");
    const toml::node* duration = t.get("duration");
    if (fps) tl.fps = in.in_interval(*fps, path / "fps", 0.0, kMaxFps, true, " frames per second");
    if (duration)
        tl.duration = in.in_interval(*duration, path / "duration", 0.0, kMaxDurationSeconds, true, " seconds");
    if (const toml::node* n = t.get("substeps"))
        tl.substeps = int(in.integer_in(*n, path / "substeps", 1, kMaxSubsteps));
    if (const toml::node* n = t.get("preroll"))
        tl.preroll = in.in_interval(*n, path / "preroll", 0.0, kMaxDurationSeconds, false, " seconds");
    if (const toml::node* n = t.get("seed"))
        tl.seed = std::uint64_t(in.integer_in(*n, path / "seed", 0, std::numeric_limits<std::int64_t>::max()));
    if (const toml::node* n = t.get("max_particles"))
        tl.max_particles = std::uint32_t(in.integer_in(*n, path / "max_particles", 1, kMaxParticles));
    if (const toml::node* n = t.get("resolution")) {
        const KeyPath p = path / "resolution";
        const toml::array* a = n->as_array();
        if (!a || a->size() != 2) in.fail(*n, p, "must be [width, height] (got " + toml_read::describe(*n) + ")");
        camera.width = int(in.integer_in((*a)[0], p[0], 1, kMaxImageSide));
        camera.height = int(in.integer_in((*a)[1], p[1], 1, kMaxImageSide));
    }
    if (tl.frame_count() < 1)  // both defaults give frames, so one of the two is present
        in.fail(*last_of({fps, duration}), path / (last_of({fps, duration}) == duration ? "duration" : "fps"),
                "duration * fps gives no frame (got " + shortest(tl.duration) + " s at " + shortest(tl.fps) + " fps)");
}

EmitterDesc::Burst read_burst(const Reader& in, const toml::table& t, const KeyPath& path) {
    in.check_keys(t, path, kBurstKeys);
    const std::string_view needs = "each burst needs time and count";
    EmitterDesc::Burst b;
    b.time = sim_time(in, in.required(t, "time", path, needs), path / "time");
    b.count = std::uint32_t(in.integer_in(in.required(t, "count", path, needs), path / "count", 0, kMaxBurstCount));
    return b;
}

// `previous`: the keys before this one, whose ages it must exceed. `albedo_max`: the emitter's largest
// albedo, which an albedo multiplier may not push above 1; null for the emission ramp (no such bound).
AgeCurves::AlbedoKey read_ramp_key(const Reader& in, const toml::table& t, const KeyPath& path,
                                   const glm::dvec3* albedo_max, const std::vector<AgeCurves::AlbedoKey>& previous) {
    in.check_keys(t, path, kRampKeys);
    const std::string needs =
        std::string("each ") + (albedo_max ? "albedo_ramp" : "emission_ramp") + " key needs age and multiplier";
    AgeCurves::AlbedoKey k;
    const toml::node& age = in.required(t, "age", path, needs);
    const KeyPath age_path = path / "age";
    k.age = in.in_interval(age, age_path, 0.0, 1.0, false);
    if (!previous.empty() && !(k.age > previous.back().age))
        in.fail(age, age_path,
                "must be greater than the previous key's age (got " + shortest(k.age) + " after " +
                    shortest(previous.back().age) + ")");
    const KeyPath mp = path / "multiplier";
    const Vec3Field m = in.vec3(in.required(t, "multiplier", path, needs), mp);
    in.each(m, mp, [](double v) { return v >= 0.0; }, "must not be negative");
    // The multiplied albedo stays a physical albedo: a medium cannot scatter more than it removes.
    in.each(m, mp, [](double v) { return v <= kMaxRadiance; }, "absurd size: must be at most 1e9");
    for (std::size_t c = 0; c < 3 && albedo_max; ++c) {
        const int ci = static_cast<int>(c);
        const double top = (*albedo_max)[ci];
        if (!(top * m.v[ci] <= 1.0))
            in.fail(*m.elems[c], mp[c],
                    "makes the albedo exceed 1 (albedo max " + shortest(top) + " * " + shortest(m.v[ci]) + " = " +
                        shortest(top * m.v[ci]) + ")");
    }
    k.multiplier = m.v;
    return k;
}

void read_curves(const Reader& in, const toml::node& node, const KeyPath& path, const glm::dvec3& albedo_max,
                 AgeCurves& c) {
    const toml::table& t = in.table(node, path, kCurveKeys);
    if (const toml::node* n = t.get("radius_growth"))
        c.radius_growth = in.non_negative(*n, path / "radius_growth", 1e6);  // a million-fold growth is a typo
    const toml::node* fade_in = t.get("fade_in");
    const toml::node* fade_out = t.get("fade_out");
    if (fade_in) c.fade_in = in.in_interval(*fade_in, path / "fade_in", 0.0, 1.0, false);
    if (fade_out) c.fade_out = in.in_interval(*fade_out, path / "fade_out", 0.0, 1.0, false);
    if (!(c.fade_in + c.fade_out <= 1.0)) {
        const toml::node* last = last_of({fade_in, fade_out});
        in.fail(*last, path / (last == fade_out ? "fade_out" : "fade_in"),
                "fade_in + fade_out must not exceed 1 (got " + shortest(c.fade_in) + " + " + shortest(c.fade_out) +
                    ")");
    }
    if (const toml::node* n = t.get("albedo_ramp")) {
        const KeyPath p = path / "albedo_ramp";
        const toml::array& a = in.inline_table_array(*n, p, kMaxListEntries, "albedo_ramp keys",
                                                     "[{ age = 0.0, multiplier = [1, 1, 1] }]");
        in.read_each(a, p, c.albedo_ramp, [&](const Reader& r, const toml::table& key, const KeyPath& key_path) {
            return read_ramp_key(r, key, key_path, &albedo_max, c.albedo_ramp);
        });
    }
    if (const toml::node* n = t.get("emission_ramp")) {
        const KeyPath p = path / "emission_ramp";
        const toml::array& a = in.inline_table_array(*n, p, kMaxListEntries, "emission_ramp keys",
                                                     "[{ age = 0.0, multiplier = [1, 1, 1] }]");
        in.read_each(a, p, c.emission_ramp, [&](const Reader& r, const toml::table& key, const KeyPath& key_path) {
            return read_ramp_key(r, key, key_path, nullptr, c.emission_ramp);
        });
    }
}

EmitterDesc read_emitter(const Reader& in, const toml::table& t, const KeyPath& path) {
    EmitterDesc e;
    e.defined_at = in.location(t);
    if (const toml::node* n = t.get("shape")) e.shape = EmitterShape(in.choice(*n, path / "shape", kShapeNames));
    const std::string_view shape_name = kShapeNames[std::size_t(e.shape)];
    // The shapes that read `key`, quoted: empty for a key every shape reads.
    const auto users = [](std::string_view key) {
        std::string names;
        for (std::size_t s = 0; s < kShapeNames.size(); ++s)
            if (contains(shape_keys(EmitterShape(s)), key))
                names += (names.empty() ? "" : ", ") + toml_text::quoted(kShapeNames[s]);
        return names;
    };
    const std::span<const std::string_view> own = shape_keys(e.shape);
    std::vector<std::string_view> allowed;
    for (const std::string_view k : kEmitterKeys)
        if (contains(own, k) || users(k).empty()) allowed.push_back(k);
    in.check_keys(t, path, allowed, kEmitterKeys, [&](std::string_view key) {
        return "not used by shape " + toml_text::quoted(shape_name) + " (it is for shape " + users(key) + ")";
    });

    if (const toml::node* n = t.get("name")) e.name = in.one_line(*n, path / "name");
    if (const toml::node* n = t.get("center")) e.center = in.coordinates(*n, path / "center");
    if (e.shape == EmitterShape::Density) {
        read_density_source(in, t, path, "a \"density\" emitter needs file", e.density_source);
        e.density_transform = read_volume_transform(in, t, path);
    }
    const std::string needs = "a " + toml_text::quoted(shape_name) + " emitter needs " +
                              (e.shape == EmitterShape::Box ? "half_extent" : "radius");
    if (e.shape == EmitterShape::Sphere || e.shape == EmitterShape::Disc)
        e.radius = in.positive(in.required(t, "radius", path, needs), path / "radius", kMaxCoordinate);
    if (e.shape == EmitterShape::Box) {
        const KeyPath p = path / "half_extent";
        const Vec3Field f = in.vec3(in.required(t, "half_extent", path, needs), p);
        in.each(f, p, [](double v) { return v >= 0.0; }, "must not be negative");
        in.each(f, p, [](double v) { return v <= kMaxCoordinate; }, "absurd size: must be at most 1e7");
        e.half_extent = f.v;
    }
    if (const toml::node* n = t.get("normal")) e.normal = in.direction(*n, path / "normal");

    if (const toml::node* n = t.get("rate")) e.rate = in.non_negative(*n, path / "rate", kMaxEmissionRate);
    const toml::node* start = t.get("start");
    const toml::node* stop = t.get("stop");
    // Times are seconds on the simulation clock (sim/simulator.h), which starts at 0 with the preroll.
    if (start) e.start = sim_time(in, *start, path / "start");
    if (stop) {
        const KeyPath p = path / "stop";
        e.stop = sim_time(in, *stop, p);
        if (!(e.stop >= e.start))
            in.fail(*last_of({start, stop}), p,
                    "must not be before start (got stop " + shortest(e.stop) + ", start " + shortest(e.start) + ")");
    }
    if (const toml::node* n = t.get("bursts")) {
        const KeyPath p = path / "bursts";
        const toml::array& a =
            in.inline_table_array(*n, p, kMaxListEntries, "bursts", "[{ time = 0.5, count = 200 }]");
        in.read_each(a, p, e.bursts, read_burst);
    }

    if (const toml::node* n = t.get("direction")) e.direction = in.direction(*n, path / "direction");
    if (const toml::node* n = t.get("speed"))
        e.speed = range(in, *n, path / "speed", [&](const toml::node& v, const KeyPath& p) {
            return in.non_negative(v, p, kMaxForce);
        });
    if (const toml::node* n = t.get("cone_deg"))
        e.cone_deg = in.in_interval(*n, path / "cone_deg", 0.0, 180.0, false, " degrees");
    if (const toml::node* n = t.get("jitter")) e.jitter = in.non_negative(*n, path / "jitter", kMaxForce);
    if (const toml::node* n = t.get("lifetime"))
        e.lifetime = range(in, *n, path / "lifetime", [&](const toml::node& v, const KeyPath& p) {
            return in.positive(v, p, kMaxTimeSeconds);
        });
    if (const toml::node* n = t.get("particle_radius"))
        e.radius_range = range(in, *n, path / "particle_radius", [&](const toml::node& v, const KeyPath& p) {
            return in.positive(v, p, kMaxCoordinate);
        });
    if (const toml::node* n = t.get("extinction"))
        e.extinction = range(in, *n, path / "extinction", [&](const toml::node& v, const KeyPath& p) {
            return in.non_negative(v, p, kMaxExtinction);
        });
    if (const toml::node* n = t.get("albedo")) e.albedo = color_range(in, *n, path / "albedo");
    if (const toml::node* n = t.get("emission")) e.emission = in.radiance(*n, path / "emission");
    if (const toml::node* n = t.get("curves")) read_curves(in, *n, path / "curves", e.albedo.max, e.curves);
    return e;
}

ForceDesc read_force(const Reader& in, const toml::table& t, const KeyPath& path) {
    ForceDesc f;
    const std::string types = "each [[force]] needs type, one of " + join(kForceNames);
    f.kind = ForceKind(in.choice(in.required(t, "type", path, types), path / "type", kForceNames));
    const std::string_view type = kForceNames[std::size_t(f.kind)];
    const std::span<const std::string_view> own = force_keys(f.kind);
    std::vector<std::string_view> allowed{"type"};
    allowed.insert(allowed.end(), own.begin(), own.end());
    in.check_keys(t, path, allowed, kForceKeys, [&](std::string_view) {
        return "not used by type " + toml_text::quoted(type) + " (" + std::string(type) + " takes " + join(own) + ")";
    });
    const std::string needs = "a " + toml_text::quoted(type) + " force needs " + join(own);
    switch (f.kind) {
        case ForceKind::Gravity:
            f.vector = force_vector(in, in.required(t, "vector", path, needs), path / "vector");
            break;
        case ForceKind::Buoyancy:  // negative: a medium denser than the air around it sinks
            f.strength = in.bounded(in.required(t, "strength", path, needs), path / "strength", kMaxForce);
            break;
        case ForceKind::Wind:  // a drag toward the wind's velocity: a negative rate would pump energy in
            f.vector = force_vector(in, in.required(t, "vector", path, needs), path / "vector");
            f.strength = in.non_negative(in.required(t, "strength", path, needs), path / "strength", kMaxForce);
            break;
        case ForceKind::Drag:
            f.strength = in.non_negative(in.required(t, "strength", path, needs), path / "strength", kMaxForce);
            break;
        case ForceKind::Turbulence:
            f.strength = in.non_negative(in.required(t, "strength", path, "a \"turbulence\" force needs strength"),
                                         path / "strength", kMaxForce);
            if (const toml::node* n = t.get("scale")) f.scale = in.positive(*n, path / "scale", kMaxForce);
            if (const toml::node* n = t.get("speed")) f.speed = in.non_negative(*n, path / "speed", kMaxForce);
            if (const toml::node* n = t.get("octaves")) f.octaves = int(in.integer_in(*n, path / "octaves", 1, 16));
            if (const toml::node* n = t.get("lacunarity"))
                f.lacunarity = in.in_interval(*n, path / "lacunarity", 1.0, 16.0, false);
            if (const toml::node* n = t.get("gain")) f.gain = in.in_interval(*n, path / "gain", 0.0, 1.0, false);
            break;
        case ForceKind::Vortex:  // the sign of strength is the sense of rotation about axis
            f.strength = in.bounded(in.required(t, "strength", path, "a \"vortex\" force needs strength"),
                                    path / "strength", kMaxForce);
            if (const toml::node* n = t.get("center")) f.center = in.coordinates(*n, path / "center");
            if (const toml::node* n = t.get("axis")) f.axis = in.direction(*n, path / "axis");
            if (const toml::node* n = t.get("radius")) f.radius = in.positive(*n, path / "radius", kMaxCoordinate);
            break;
    }
    return f;
}

// `previous`: the keys before this one, whose times it must follow.
CameraKey read_camera_key(const Reader& in, const toml::table& t, const KeyPath& path, const Camera& camera,
                          const std::vector<CameraKey>& previous) {
    in.check_keys(t, path, kCameraKeyKeys);
    const std::string_view needs = "each camera key needs time, position, look_at";
    CameraKey k;
    const toml::node& key_time = in.required(t, "time", path, needs);
    const KeyPath time_path = path / "time";
    k.time = sim_time(in, key_time, time_path);
    if (!previous.empty() && !(k.time > previous.back().time))
        in.fail(key_time, time_path,
                "must be later than the previous key's time (got " + shortest(k.time) + " after " +
                    shortest(previous.back().time) + ")");
    k.position = in.coordinates(in.required(t, "position", path, needs), path / "position");
    const toml::node& look_at = in.required(t, "look_at", path, needs);
    const KeyPath look_path = path / "look_at";
    k.look_at = in.coordinates(look_at, look_path);
    check_view(in, look_at.source(), look_path, k.position, k.look_at, camera.up,
               "must differ from position (they are the same point)");
    return k;
}

void read_camera_path(const Reader& in, const toml::node& node, const KeyPath& path, const Camera& camera,
                      CameraPath& cp) {
    const toml::table& t = in.table(node, path);
    const std::string types = "[camera_path] needs type, one of " + join(kCameraPathNames);
    cp.kind = CameraPath::Kind(in.choice(in.required(t, "type", path, types), path / "type", kCameraPathNames));
    const std::string_view type = kCameraPathNames[std::size_t(cp.kind)];
    const std::span<const std::string_view> own = camera_path_keys(cp.kind);
    std::vector<std::string_view> allowed{"type"};
    allowed.insert(allowed.end(), own.begin(), own.end());
    in.check_keys(t, path, allowed, kCameraPathKeys, [&](std::string_view) {
        return "not used by type " + toml_text::quoted(type) +
               (own.empty() ? std::string(" (it takes no other key)")
                            : " (" + std::string(type) + " takes " + join(own) + ")");
    });
    switch (cp.kind) {
        case CameraPath::Kind::Static: break;
        case CameraPath::Kind::Keyframes: {
            const toml::node& keys = in.required(t, "keys", path, "a \"keyframes\" path needs keys");
            const KeyPath p = path / "keys";
            const toml::array& a = in.inline_table_array(keys, p, kMaxListEntries, "camera keys",
                                                         "[{ time = 0.0, position = [0, 1, 6], look_at = [0, 1, 0] }]");
            // Each key is read before they are counted, so a typo in a lone key is named, not hidden
            // behind "needs at least 2 keys".
            in.read_each(a, p, cp.keys, [&](const Reader& r, const toml::table& key, const KeyPath& key_path) {
                return read_camera_key(r, key, key_path, camera, cp.keys);
            });
            if (a.size() < 2) in.fail(keys, p, "needs at least 2 keys (got " + std::to_string(a.size()) + ")");
            break;
        }
        case CameraPath::Kind::Orbit: {
            if (const toml::node* n = t.get("center")) cp.orbit_center = in.coordinates(*n, path / "center");
            // The eye circles at `radius` around the vertical axis, looking at center: radius 0
            // would look straight down the axis, parallel to a vertical up.
            if (const toml::node* n = t.get("radius"))
                cp.orbit_radius = in.positive(*n, path / "radius", kMaxCoordinate);
            if (const toml::node* n = t.get("height"))
                cp.orbit_height = in.bounded(*n, path / "height", kMaxCoordinate);
            if (const toml::node* n = t.get("start_deg"))
                cp.orbit_start_deg = in.bounded(*n, path / "start_deg", kMaxTimeSeconds);
            if (const toml::node* n = t.get("deg_per_second"))
                cp.orbit_deg_per_second = in.bounded(*n, path / "deg_per_second", kMaxTimeSeconds);
            break;
        }
    }
}

void read_render_settings(const Reader& in, const toml::node& node, const KeyPath& path, RenderSettingsPreset& r) {
    const toml::table& t = in.table(node, path, kRenderSettingsKeys);
    if (const toml::node* n = t.get("method"))
        r.method = std::string(kMethodNames[in.choice(*n, path / "method", kMethodNames)]);
    if (const toml::node* n = t.get("exposure"))
        r.exposure = in.in_interval(*n, path / "exposure", -kMaxExposureStops, kMaxExposureStops, false, " stops");
}

}  // namespace

std::span<const std::string_view> force_keys(ForceKind k) {
    switch (k) {
        case ForceKind::Gravity: return kGravityKeys;
        case ForceKind::Buoyancy: return kStrengthKey;
        case ForceKind::Wind: return kWindKeys;
        case ForceKind::Drag: return kStrengthKey;
        case ForceKind::Turbulence: return kTurbulenceKeys;
        case ForceKind::Vortex: return kVortexKeys;
    }
    return kNoKeys;
}

void check_preset_root_keys(const Reader& in) {
    // The scene's sections first: a key both could hold is pointed to the scene's.
    in.check_root_keys(kPresetRootKeys, {kSceneSectionHints, kPresetSectionHints});
}

void read_preset_header(const Reader& in, Preset& p) {
    const KeyPath top;
    if (const toml::node* n = in.root().get("preset")) read_preset(in, *n, top / "preset", p);
}

void read_preset_sections(const Reader& in, Preset& p) {
    const toml::table& root = in.root();
    const KeyPath top;
    // After [camera]: its resolution overrides the camera's size.
    if (const toml::node* n = root.get("timeline")) read_timeline(in, *n, top / "timeline", p.timeline, p.scene.camera);
    if (const toml::node* n = root.get("emitter"))
        in.read_each(*n, top / "emitter", kMaxEmitters, "emitters", p.emitters, read_emitter);
    if (const toml::node* n = root.get("force"))
        in.read_each(*n, top / "force", kMaxForces, "forces", p.forces, read_force);
    // After [camera]: keyframes are checked against its up vector.
    if (const toml::node* n = root.get("camera_path"))
        read_camera_path(in, *n, top / "camera_path", p.scene.camera, p.camera_path);
    if (const toml::node* n = root.get("render_settings"))
        read_render_settings(in, *n, top / "render_settings", p.render);
}

}  // namespace brume
