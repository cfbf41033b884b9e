#include "sim/preset_file.h"

#include "sim/volume_transform.h"

#include <glm/geometric.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace brume {

namespace {

using toml_text::shortest;
using toml_text::suggest;

// Keys are printed bare when TOML would allow them bare.
std::string quote_key(std::string_view k) {
    const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
               c == '-';
    });
    return bare ? std::string(k) : toml_text::quoted(k);
}

// A key path as a chain of stack frames, formatted only when an error needs it: parsing a million
// spheres builds no strings. Extending a temporary is deleted, so no path outlives its parent.
struct KeyPath {
    const KeyPath* parent = nullptr;  // nullptr: the document root, printed as nothing
    std::string_view key;             // this element's key (may be ""), when index < 0
    std::ptrdiff_t index = -1;        // or this element's array index

    KeyPath operator/(std::string_view k) const& { return KeyPath{this, k, -1}; }
    KeyPath operator/(std::string_view k) const&& = delete;
    KeyPath operator[](std::size_t i) const& { return KeyPath{this, {}, static_cast<std::ptrdiff_t>(i)}; }
    KeyPath operator[](std::size_t i) const&& = delete;

    std::string str() const {
        if (!parent) return {};
        std::string s = parent->str();
        if (index >= 0) return s + '[' + std::to_string(index) + ']';
        if (!s.empty()) s += '.';
        return s + quote_key(key);
    }
};

std::string join(std::span<const std::string_view> names) {
    std::string s;
    for (const std::string_view n : names) {
        if (!s.empty()) s += ", ";
        s += n;
    }
    return s;
}

bool contains(std::span<const std::string_view> names, std::string_view name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

// "1e7" rather than to_chars' "1e+07" in messages about limits.
std::string limit_text(double v) {
    std::string s = shortest(v);
    const std::size_t e = s.find("e+");
    if (e != std::string::npos) {
        std::size_t digits = e + 2;
        while (digits + 1 < s.size() && s[digits] == '0') ++digits;
        s = s.substr(0, e + 1) + s.substr(digits);
    }
    return s;
}

// The schema, in the order keys are checked and written.
constexpr std::array<std::string_view, 6> kSceneRootKeys{"camera", "lighting", "render", "box", "sphere", "vdb"};
constexpr std::array<std::string_view, 12> kPresetRootKeys{
    "preset", "timeline", "camera", "lighting", "render", "box", "sphere", "vdb", "emitter", "force", "camera_path",
    "render_settings"};
constexpr std::array<std::string_view, 6> kCameraKeys{"position", "look_at", "up", "fov_y_deg", "width", "height"};
constexpr std::array<std::string_view, 4> kLightingKeys{"ambient", "sun", "sun_direction", "background"};
constexpr std::array<std::string_view, 1> kRenderKeys{"min_transmittance"};
constexpr std::array<std::string_view, 3> kBoxKeys{"min", "max", "radiance"};
constexpr std::array<std::string_view, 4> kSphereKeys{"center", "radius", "extinction", "albedo"};
constexpr std::array<std::string_view, 10> kVdbKeys{"file",        "grid",        "albedo_grid", "extinction_scale",
                                                    "albedo",      "tolerance",   "max_spheres", "translate",
                                                    "scale",       "rotate"};

constexpr std::array<std::string_view, 2> kPresetKeys{"name", "description"};
constexpr std::array<std::string_view, 7> kTimelineKeys{"fps",  "duration",      "substeps",  "preroll",
                                                        "seed", "max_particles", "resolution"};
constexpr std::array<std::string_view, 24> kEmitterKeys{
    "name",      "shape",    "center", "radius",   "half_extent",     "normal",     "file",   "grid",
    "translate", "scale",    "rotate", "rate",     "start",           "stop",       "bursts", "direction",
    "speed",     "cone_deg", "jitter", "lifetime", "particle_radius", "extinction", "albedo", "curves"};
constexpr std::array<std::string_view, 2> kBurstKeys{"time", "count"};
constexpr std::array<std::string_view, 4> kCurveKeys{"radius_growth", "fade_in", "fade_out", "albedo_ramp"};
constexpr std::array<std::string_view, 2> kRampKeys{"age", "multiplier"};
constexpr std::array<std::string_view, 2> kColorRangeKeys{"min", "max"};
constexpr std::array<std::string_view, 11> kForceKeys{"type",   "vector",     "strength", "scale",
                                                      "speed",  "octaves",    "lacunarity", "gain",
                                                      "center", "axis",       "radius"};
constexpr std::array<std::string_view, 7> kCameraPathKeys{"type",   "keys",      "center",        "radius",
                                                          "height", "start_deg", "deg_per_second"};
constexpr std::array<std::string_view, 3> kCameraKeyKeys{"time", "position", "look_at"};
constexpr std::array<std::string_view, 2> kRenderSettingsKeys{"method", "exposure"};

// Names in enum order.
constexpr std::array<std::string_view, 5> kShapeNames{"point", "sphere", "box", "disc", "density"};
constexpr std::array<std::string_view, 6> kForceNames{"gravity", "buoyancy", "wind", "drag", "turbulence", "vortex"};
constexpr std::array<std::string_view, 3> kCameraPathNames{"static", "keyframes", "orbit"};
constexpr std::array<std::string_view, 2> kMethodNames{"ppll", "reference"};

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

std::span<const std::string_view> camera_path_keys(CameraPath::Kind k) {
    switch (k) {
        case CameraPath::Kind::Static: return kNoKeys;
        case CameraPath::Kind::Keyframes: return kKeyframesKeys;
        case CameraPath::Kind::Orbit: return kOrbitKeys;
    }
    return kNoKeys;
}

// Where a key misplaced at the top level belongs, in the order the hint is looked for.
struct Section {
    std::span<const std::string_view> keys;
    const char* hint;
    bool preset_only;
};
const std::array<Section, 12> kSections{{
    {kCameraKeys, "it belongs under [camera]", false},
    {kLightingKeys, "it belongs under [lighting]", false},
    {kRenderKeys, "it belongs under [render]", false},
    {kBoxKeys, "it belongs in a [[box]] section", false},
    {kSphereKeys, "it belongs in a [[sphere]] section", false},
    {kVdbKeys, "it belongs in a [[vdb]] section", false},
    {kPresetKeys, "it belongs under [preset]", true},
    {kTimelineKeys, "it belongs under [timeline]", true},
    {kEmitterKeys, "it belongs in an [[emitter]] section", true},
    {kForceKeys, "it belongs in a [[force]] section", true},
    {kCameraPathKeys, "it belongs under [camera_path]", true},
    {kRenderSettingsKeys, "it belongs under [render_settings]", true},
}};

std::string describe(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array of " + std::to_string(n.as_array()->size()) + " element(s)";
        case toml::node_type::string: {
            const std::string_view v = n.as_string()->get();
            return "a string " + toml_text::quoted(v.substr(0, 40)) + (v.size() > 40 ? "..." : "");
        }
        case toml::node_type::integer: return "an integer " + std::to_string(n.as_integer()->get());
        case toml::node_type::floating_point: {
            std::string s = "a floating-point number ";
            toml_text::append_float(s, n.as_floating_point()->get());
            return s;
        }
        case toml::node_type::boolean: return n.as_boolean()->get() ? "a boolean true" : "a boolean false";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        case toml::node_type::none: break;
    }
    return "nothing";
}

// "[camra]" is reported as a table, "raduis = 1" as a key.
std::string unknown_what(const toml::node& n) {
    return n.is_table() || n.is_array_of_tables() ? "unknown table" : "unknown key";
}

struct Vec3Field {
    glm::dvec3 v{0.0};
    std::array<const toml::node*, 3> elems{};
};

class Parser {
public:
    Parser(const std::string& file, DocumentKind kind) : file_(file), kind_(kind) {}

    Preset document(const toml::table& root) const {
        Preset p;
        check_root_keys(root);
        const KeyPath top;
        if (const toml::node* n = root.get("preset")) preset(*n, top / "preset", p);
        Scene& s = p.scene;
        if (const toml::node* n = root.get("camera")) camera(*n, top / "camera", s.camera);
        if (const toml::node* n = root.get("lighting")) lighting(*n, top / "lighting", s.lighting);
        if (const toml::node* n = root.get("render")) render(*n, top / "render", s.render);
        if (const toml::node* n = root.get("box")) boxes(*n, top / "box", s.boxes);
        if (const toml::node* n = root.get("sphere")) spheres(*n, top / "sphere", s.spheres);
        if (const toml::node* n = root.get("vdb")) volumes(*n, top / "vdb", s.volumes);
        // Four lines of TOML render a .vdb: with no camera placement given, the loader frames the volumes.
        {
            const toml::table* camera_table = root.get("camera") ? root.get("camera")->as_table() : nullptr;
            const bool placed = camera_table && (camera_table->get("position") || camera_table->get("look_at"));
            s.frame_volumes = !s.volumes.empty() && !placed;
        }
        // After [camera]: its resolution overrides the camera's size.
        if (const toml::node* n = root.get("timeline")) timeline(*n, top / "timeline", p.timeline, s.camera);
        if (const toml::node* n = root.get("emitter")) emitters(*n, top / "emitter", p.emitters);
        if (const toml::node* n = root.get("force")) forces(*n, top / "force", p.forces);
        // After [camera]: keyframes are checked against its up vector.
        if (const toml::node* n = root.get("camera_path"))
            camera_path(*n, top / "camera_path", s.camera, p.camera_path);
        if (const toml::node* n = root.get("render_settings")) render_settings(*n, top / "render_settings", p.render);
        s.source = file_;
        if (p.name.empty()) p.name = std::filesystem::path(file_).stem().string();
        return p;
    }

private:
    [[noreturn]] void fail(const toml::source_region& where, const KeyPath& path, const std::string& problem) const {
        throw SceneFileError(file_, static_cast<int>(where.begin.line), 0, path.str(), problem);
    }
    [[noreturn]] void fail(const toml::node& n, const KeyPath& path, const std::string& problem) const {
        fail(n.source(), path, problem);
    }

    // The first key in the file that is not in `allowed`. A key in `elsewhere` (used by another shape or
    // type) is explained by `misplaced`; any other gets a suggestion from `allowed` when one is close.
    template <class Misplaced>
    void check_keys(const toml::table& t, const KeyPath& table_path, std::span<const std::string_view> allowed,
                    std::span<const std::string_view> elsewhere, Misplaced misplaced) const {
        const toml::key* first = nullptr;
        for (auto&& [k, v] : t) {
            if (contains(allowed, k.str())) continue;
            if (!first || k.source().begin < first->source().begin) first = &k;
        }
        if (!first) return;
        const std::string_view name = first->str();
        std::string problem;
        if (contains(elsewhere, name))
            problem = misplaced(name);
        else if (const auto s = suggest(name, allowed))
            problem = unknown_what(t.at(name)) + " (did you mean \"" + std::string(*s) + "\"?)";
        else
            problem = unknown_what(t.at(name)) + " (allowed here: " + join(allowed) + ")";
        fail(first->source(), table_path / name, problem);
    }
    void check_keys(const toml::table& t, const KeyPath& table_path, std::span<const std::string_view> known) const {
        check_keys(t, table_path, known, {}, [](std::string_view) { return std::string(); });
    }

    // At the top level a preset section in a scene file, or a key above its section ("width" above
    // [camera]), is pointed to where it belongs.
    void check_root_keys(const toml::table& root) const {
        const bool scene_only = kind_ == DocumentKind::Scene;
        const std::span<const std::string_view> known =
            scene_only ? std::span<const std::string_view>(kSceneRootKeys) : kPresetRootKeys;
        const toml::key* first = nullptr;
        for (auto&& [k, v] : root) {
            if (contains(known, k.str())) continue;
            if (!first || k.source().begin < first->source().begin) first = &k;
        }
        if (!first) return;
        const std::string_view name = first->str();
        std::string problem = unknown_what(root.at(name));
        const Section* home = nullptr;
        for (const Section& s : kSections)
            if (!home && (!scene_only || !s.preset_only) && contains(s.keys, name)) home = &s;
        if (scene_only && contains(kPresetRootKeys, name))
            problem = "a preset section: not allowed in a static scene file (read the file as a preset)";
        else if (const auto s = suggest(name, known))
            problem += " (did you mean \"" + std::string(*s) + "\"?)";
        else if (home)
            problem += " (" + std::string(home->hint) + ")";
        else
            problem += " (allowed at the top level: " + join(known) + ")";
        const KeyPath top;
        fail(first->source(), top / name, problem);
    }

    const toml::table& table(const toml::node& n, const KeyPath& path) const {
        const toml::table* t = n.as_table();
        if (!t) fail(n, path, "must be a table (got " + describe(n) + ")");
        return *t;
    }

    // A top-level array of tables ([[box]]), its length checked against a limit, each element a table.
    const toml::array& table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                   const char* what) const {
        const std::string header = "[[" + std::string(path.key) + "]]";
        const toml::array* a = n.as_array();
        if (!a) {
            std::string problem = "must be an array of tables (got " + describe(n) + ")";
            if (n.is_table()) problem += ": write " + header + ", not [" + std::string(path.key) + "]";
            else problem += ": write each as a " + header + " section";
            fail(n, path, problem);
        }
        return elements_are_tables(*a, path, limit, what);
    }

    // An array of inline tables inside a section (bursts = [{ time = 0.5, count = 200 }]).
    const toml::array& inline_table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                          const char* what, const char* example) const {
        const toml::array* a = n.as_array();
        if (!a)
            fail(n, path, "must be an array of tables such as " + std::string(example) + " (got " + describe(n) + ")");
        return elements_are_tables(*a, path, limit, what);
    }

    const toml::array& elements_are_tables(const toml::array& a, const KeyPath& path, std::size_t limit,
                                           const char* what) const {
        if (a.size() > limit)
            fail(a, path,
                 "absurd size: too many " + std::string(what) + " (got " + std::to_string(a.size()) +
                     ", the limit is " + std::to_string(limit) + ")");
        for (std::size_t i = 0; i < a.size(); ++i)
            if (!a[i].is_table()) fail(a[i], path[i], "must be a table (got " + describe(a[i]) + ")");
        return a;
    }

    // A key the section cannot do without; the error points at the section's header.
    const toml::node& required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                               std::string_view needs) const {
        const toml::node* n = t.get(key);
        if (!n) fail(t.source(), table_path / key, "missing (" + std::string(needs) + ")");
        return *n;
    }
    // In a top-level [[section]], every key of which is required.
    const toml::node& required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                               std::span<const std::string_view> all) const {
        const toml::node* n = t.get(key);
        if (!n)
            fail(t.source(), table_path / key,
                 "missing (each [[" + std::string(table_path.parent->key) + "]] needs " + join(all) + ")");
        return *n;
    }

    // --- Scalars ---------------------------------------------------------------------------------

    // Integers are accepted where floats are expected; NaN and Inf never are.
    double number(const toml::node& n, const KeyPath& path) const {
        double v = 0.0;
        if (const auto* i = n.as_integer())
            v = static_cast<double>(i->get());
        else if (const auto* f = n.as_floating_point())
            v = f->get();
        else
            fail(n, path, "must be a number (got " + describe(n) + ")");
        if (!std::isfinite(v)) fail(n, path, "must be finite (got " + shortest(v) + ")");
        return v;
    }

    double at_most(const toml::node& n, const KeyPath& path, double v, double max) const {
        if (!(v <= max))
            fail(n, path, "absurd size: must be at most " + limit_text(max) + " (got " + shortest(v) + ")");
        return v;
    }

    double non_negative(const toml::node& n, const KeyPath& path, double max) const {
        const double v = number(n, path);
        if (!(v >= 0.0)) fail(n, path, "must not be negative (got " + shortest(v) + ")");
        return at_most(n, path, v, max);
    }

    double positive(const toml::node& n, const KeyPath& path, double max) const {
        const double v = number(n, path);
        if (!(v > 0.0)) fail(n, path, "must be positive (got " + shortest(v) + ")");
        return at_most(n, path, v, max);
    }

    // |v| <= max: a signed quantity of bounded size.
    double bounded(const toml::node& n, const KeyPath& path, double max) const {
        const double v = number(n, path);
        if (!(std::abs(v) <= max))
            fail(n, path, "absurd size: must be within " + limit_text(max) + " of 0 (got " + shortest(v) + ")");
        return v;
    }

    // lo <= v <= hi, or lo < v <= hi when open_below; `unit` follows the interval in the message.
    double in_interval(const toml::node& n, const KeyPath& path, double lo, double hi, bool open_below,
                       const char* unit = "") const {
        const double v = number(n, path);
        if (!((open_below ? v > lo : v >= lo) && v <= hi))
            fail(n, path,
                 std::string("must be in ") + (open_below ? "(" : "[") + limit_text(lo) + ", " + limit_text(hi) + "]" +
                     unit + " (got " + shortest(v) + ")");
        return v;
    }

    // Seconds since the start of the simulation, preroll included.
    double time(const toml::node& n, const KeyPath& path) const {
        return in_interval(n, path, 0.0, kMaxTimeSeconds, false, " seconds");
    }

    std::int64_t integer_in(const toml::node& n, const KeyPath& path, std::int64_t lo, std::int64_t hi) const {
        const auto* i = n.as_integer();
        if (!i) fail(n, path, "must be an integer (got " + describe(n) + ")");
        const std::int64_t v = i->get();
        if (v < lo || v > hi)
            fail(n, path,
                 "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " +
                     std::to_string(v) + ")");
        return v;
    }

    std::string_view string(const toml::node& n, const KeyPath& path) const {
        const auto* s = n.as_string();
        if (!s) fail(n, path, "must be a string (got " + describe(n) + ")");
        return s->get();
    }

    // Names and descriptions are printed on one line (`brume play --list`, messages).
    std::string one_line(const toml::node& n, const KeyPath& path) const {
        const std::string_view s = string(n, path);
        if (std::any_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
            fail(n, path, "must be one line of text without control characters (got " + toml_text::quoted(s) + ")");
        return std::string(s);
    }

    // One of `names`; returns its index (the enum value).
    std::size_t choice(const toml::node& n, const KeyPath& path, std::span<const std::string_view> names) const {
        const std::string_view s = string(n, path);
        const auto it = std::find(names.begin(), names.end(), s);
        if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
        std::string problem = "must be one of";
        for (std::size_t i = 0; i < names.size(); ++i)
            problem += std::string(i ? ", " : " ") + toml_text::quoted(names[i]);
        problem += " (got " + toml_text::quoted(s);
        if (const auto close = suggest(s, names)) problem += "; did you mean " + toml_text::quoted(*close) + "?";
        fail(n, path, problem + ")");
    }

    // --- Vectors and ranges ----------------------------------------------------------------------

    Vec3Field vec3(const toml::node& n, const KeyPath& path) const {
        const toml::array* a = n.as_array();
        if (!a) fail(n, path, "must be an array of 3 numbers (got " + describe(n) + ")");
        if (a->size() != 3)
            fail(n, path, "must be an array of exactly 3 numbers (got " + std::to_string(a->size()) + ")");
        Vec3Field f;
        for (std::size_t c = 0; c < 3; ++c) {
            f.elems[c] = &(*a)[c];
            f.v[static_cast<int>(c)] = number(*f.elems[c], path[c]);
        }
        return f;
    }

    template <class Ok>
    void each(const Vec3Field& f, const KeyPath& path, Ok ok, const char* rule) const {
        for (std::size_t c = 0; c < 3; ++c) {
            const double v = f.v[static_cast<int>(c)];
            if (!ok(v)) fail(*f.elems[c], path[c], std::string(rule) + " (got " + shortest(v) + ")");
        }
    }

    // A position or direction: bounded so that squaring it (lengths, intersections) stays finite.
    glm::dvec3 coordinates(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return std::abs(v) <= kMaxCoordinate; },
             "absurd size: coordinates must be within 1e7 of the origin");
        return f.v;
    }

    // A direction that is normalised where it is used.
    glm::dvec3 direction(const toml::node& n, const KeyPath& path) const {
        const glm::dvec3 v = coordinates(n, path);
        if (!(glm::length(v) > 0.0)) fail(n, path, "must not be zero (it is normalised)");
        return v;
    }

    // An acceleration or velocity.
    glm::dvec3 force_vector(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return std::abs(v) <= kMaxForce; }, "absurd size: must be within 1e6 of 0");
        return f.v;
    }

    glm::dvec3 radiance(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return v >= 0.0; }, "must not be negative");
        each(f, path, [](double v) { return v <= kMaxRadiance; }, "absurd size: must be at most 1e9");
        return f.v;
    }

    Vec3Field albedo(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return v >= 0.0 && v <= 1.0; }, "must be in [0, 1]");
        return f;
    }

    // `[min, max]` or one number for both; `element` reads and checks each bound.
    template <class Element>
    Range range(const toml::node& n, const KeyPath& path, Element element) const {
        if (n.is_integer() || n.is_floating_point()) {
            const double v = element(n, path);
            return {v, v};
        }
        const toml::array* a = n.as_array();
        if (!a) fail(n, path, "must be a number or [min, max] (got " + describe(n) + ")");
        if (a->size() != 2)
            fail(n, path, "must be [min, max], an array of exactly 2 numbers (got " + std::to_string(a->size()) + ")");
        const Range r{element((*a)[0], path[0]), element((*a)[1], path[1])};
        if (!(r.min <= r.max))
            fail(n, path, "min must not exceed max (got [" + shortest(r.min) + ", " + shortest(r.max) + "])");
        return r;
    }

    // `[r, g, b]` for a constant, or `{ min = [r, g, b], max = [r, g, b] }`.
    ColorRange color_range(const toml::node& n, const KeyPath& path) const {
        if (n.is_array()) {
            const glm::dvec3 c = albedo(n, path).v;
            return {c, c};
        }
        const toml::table* t = n.as_table();
        if (!t) fail(n, path, "must be [r, g, b] or { min = [r, g, b], max = [r, g, b] } (got " + describe(n) + ")");
        check_keys(*t, path, kColorRangeKeys);
        const std::string_view needs = "albedo as a table needs min and max";
        const KeyPath min_path = path / "min";
        const KeyPath max_path = path / "max";
        const Vec3Field lo = albedo(required(*t, "min", path, needs), min_path);
        const Vec3Field hi = albedo(required(*t, "max", path, needs), max_path);
        for (std::size_t c = 0; c < 3; ++c) {
            const int i = static_cast<int>(c);
            if (!(lo.v[i] <= hi.v[i]))
                fail(*hi.elems[c], max_path[c],
                     "must not be below min (got max " + shortest(hi.v[i]) + ", min " + shortest(lo.v[i]) + ")");
        }
        return {lo.v, hi.v};
    }

    // The line of the last present key among candidates, else the table's: where a cross-key error points.
    static const toml::source_region& where(const toml::table& t, std::initializer_list<const toml::node*> nodes) {
        const toml::source_region* r = &t.source();
        for (const toml::node* n : nodes)
            if (n && (r == &t.source() || r->begin < n->source().begin)) r = &n->source();
        return *r;
    }

    // The present node that comes last in the file (nullptr if none): where a cross-key error points.
    static const toml::node* last_of(std::initializer_list<const toml::node*> nodes) {
        const toml::node* last = nullptr;
        for (const toml::node* n : nodes)
            if (n && (!last || last->source().begin < n->source().begin)) last = n;
        return last;
    }

    // The view direction must be defined and not parallel to up (make_camera_rays normalises both).
    void check_view(const toml::source_region& at, const KeyPath& path, const glm::dvec3& position,
                    const glm::dvec3& look_at, const glm::dvec3& up, const char* same_point) const {
        const glm::dvec3 view = look_at - position;
        const double view_length = glm::length(view);
        if (!(view_length > 0.0)) fail(at, path, same_point);
        const double up_length = glm::length(up);
        // sin(angle) below 1e-9 leaves the basis ill-conditioned; the camera has no defined roll.
        if (up_length > 0.0 && !(glm::length(glm::cross(view / view_length, up / up_length)) > 1e-9))
            fail(at, path, "the view direction (look_at - position) must not be parallel to camera.up");
    }

    // --- Scene sections --------------------------------------------------------------------------

    void camera(const toml::node& node, const KeyPath& path, Camera& c) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kCameraKeys);
        const toml::node* position = t.get("position");
        const toml::node* look_at = t.get("look_at");
        const toml::node* up = t.get("up");
        if (position) c.position = coordinates(*position, path / "position");
        if (look_at) c.look_at = coordinates(*look_at, path / "look_at");
        if (up) c.up = coordinates(*up, path / "up");
        if (const toml::node* n = t.get("fov_y_deg")) {
            const KeyPath p = path / "fov_y_deg";
            c.fov_y_deg = number(*n, p);
            if (!(c.fov_y_deg > 0.0 && c.fov_y_deg <= kMaxFovYDeg))
                fail(*n, p, "must be in (0, 179] degrees (got " + shortest(c.fov_y_deg) + ")");
        }
        if (const toml::node* n = t.get("width")) c.width = int(integer_in(*n, path / "width", 1, kMaxImageSide));
        if (const toml::node* n = t.get("height")) c.height = int(integer_in(*n, path / "height", 1, kMaxImageSide));

        // make_camera_rays normalises look_at - position and cross(forward, up): both must be well defined.
        const glm::dvec3 view = c.look_at - c.position;
        const double view_length = glm::length(view);
        if (!(view_length > 0.0))
            fail(where(t, {position, look_at}), path / (look_at ? "look_at" : "position"),
                 "position and look_at must differ (they are the same point)");
        const double up_length = glm::length(c.up);
        if (!(up_length > 0.0)) fail(where(t, {up}), path / "up", "must not be zero");
        const double sin_angle = glm::length(glm::cross(view / view_length, c.up / up_length));
        if (!(sin_angle > 1e-9))
            fail(where(t, {position, look_at, up}), path / "up",
                 "must not be parallel to the view direction (look_at - position)");
    }

    void lighting(const toml::node& node, const KeyPath& path, Lighting& l) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kLightingKeys);
        if (const toml::node* n = t.get("ambient")) l.ambient = radiance(*n, path / "ambient");
        if (const toml::node* n = t.get("sun")) l.sun = radiance(*n, path / "sun");
        if (const toml::node* n = t.get("sun_direction")) l.sun_direction = direction(*n, path / "sun_direction");
        if (const toml::node* n = t.get("background")) l.background = radiance(*n, path / "background");
    }

    void render(const toml::node& node, const KeyPath& path, RenderSettings& r) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kRenderKeys);
        if (const toml::node* n = t.get("min_transmittance")) {
            const KeyPath p = path / "min_transmittance";
            r.min_transmittance = number(*n, p);
            if (!(r.min_transmittance >= 0.0 && r.min_transmittance < 1.0))
                fail(*n, p, "must be in [0, 1) (got " + shortest(r.min_transmittance) + ")");
        }
    }

    void boxes(const toml::node& node, const KeyPath& array_path, std::vector<Box>& out) const {
        const toml::array& a = table_array(node, array_path, kMaxBoxes, "boxes");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const KeyPath path = array_path[i];
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kBoxKeys);
            Box b;
            b.min = coordinates(required(t, "min", path, kBoxKeys), path / "min");
            const toml::node& max = required(t, "max", path, kBoxKeys);
            b.max = coordinates(max, path / "max");
            b.radiance = radiance(required(t, "radiance", path, kBoxKeys), path / "radiance");
            for (int c = 0; c < 3; ++c) {
                if (!(b.min[c] < b.max[c])) {
                    const char axis = "xyz"[c];
                    fail(max, path / "max",
                         std::string("must exceed min on every axis (max.") + axis + " = " + shortest(b.max[c]) +
                             ", min." + axis + " = " + shortest(b.min[c]) + ")");
                }
            }
            out.push_back(b);
        }
    }

    void spheres(const toml::node& node, const KeyPath& array_path, std::vector<Sphere>& out) const {
        const toml::array& a = table_array(node, array_path, kMaxSpheres, "spheres");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const KeyPath path = array_path[i];
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kSphereKeys);
            Sphere s;
            s.center = coordinates(required(t, "center", path, kSphereKeys), path / "center");
            {
                const toml::node& n = required(t, "radius", path, kSphereKeys);
                const KeyPath p = path / "radius";
                s.radius = number(n, p);
                if (!(s.radius > 0.0)) fail(n, p, "must be positive and finite (got " + shortest(s.radius) + ")");
                at_most(n, p, s.radius, kMaxCoordinate);
            }
            {
                const toml::node& n = required(t, "extinction", path, kSphereKeys);
                s.extinction = non_negative(n, path / "extinction", kMaxExtinction);
            }
            s.albedo = albedo(required(t, "albedo", path, kSphereKeys), path / "albedo").v;
            out.push_back(s);
        }
    }

    void volumes(const toml::node& node, const KeyPath& array_path, std::vector<VdbVolume>& out) const {
        const toml::array& a = table_array(node, array_path, kMaxVolumes, "[[vdb]] volumes");
        out.resize(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) volume(*a[i].as_table(), array_path[i], out[i]);
    }

    void volume(const toml::table& t, const KeyPath& path, VdbVolume& v) const {
        check_keys(t, path, kVdbKeys);
        density_source(t, path, "each [[vdb]] needs file", v.source);
        // "" turns off the default (the file's "albedo" grid when it has one).
        if (const toml::node* n = t.get("albedo_grid")) v.albedo_grid = one_line(*n, path / "albedo_grid");
        if (const toml::node* n = t.get("extinction_scale"))
            v.extinction_scale = positive(*n, path / "extinction_scale", kMaxExtinction);
        if (const toml::node* n = t.get("albedo")) v.albedo = uniform_albedo(*n, path / "albedo");
        // Two ways to say how fine the conversion is: meeting both at once is not generally possible.
        const toml::node* tolerance = t.get("tolerance");
        const toml::node* max_spheres = t.get("max_spheres");
        if (tolerance && max_spheres) {
            const toml::node* last = last_of({tolerance, max_spheres});
            fail(*last, path / (last == tolerance ? "tolerance" : "max_spheres"),
                 "give tolerance or max_spheres, not both (tolerance: the accuracy to meet; max_spheres: the "
                 "most spheres to spend)");
        }
        if (tolerance) v.tolerance = in_interval(*tolerance, path / "tolerance", 0.0, 1.0, true);
        if (max_spheres)
            v.max_spheres = std::size_t(integer_in(*max_spheres, path / "max_spheres", 1, std::int64_t(kMaxSpheres)));
        v.transform = volume_transform(t, path);
    }

    // `file` (required) and `grid`: where a [[vdb]] volume or a density emitter reads its grid. The file
    // is not opened here: brume_sim does not link OpenVDB, and a relative path is taken against the
    // directory of the file that names it, which load_*_file sets afterwards.
    void density_source(const toml::table& t, const KeyPath& path, std::string_view needs, DensitySource& s) const {
        const KeyPath file_path = path / "file";
        const toml::node& file = required(t, "file", path, std::string(needs) + ": a .vdb path or builtin:NAME");
        s.file = one_line(file, file_path);
        if (s.file.empty()) fail(file, file_path, "must not be empty (a .vdb path or builtin:NAME)");
        if (const toml::node* n = t.get("grid")) s.grid = grid_name(*n, path / "grid");
    }

    // A grid's name, as OpenVDB files store it: any non-empty line of text.
    std::string grid_name(const toml::node& n, const KeyPath& path) const {
        std::string name = one_line(n, path);
        if (name.empty()) fail(n, path, "must not be empty (it names a grid in the file)");
        return name;
    }

    // One number for grey, or [r, g, b]; each in [0, 1].
    glm::dvec3 uniform_albedo(const toml::node& n, const KeyPath& path) const {
        if (n.is_integer() || n.is_floating_point()) return glm::dvec3(in_interval(n, path, 0.0, 1.0, false));
        if (!n.is_array()) fail(n, path, "must be a number or [r, g, b] (got " + describe(n) + ")");
        return albedo(n, path).v;
    }

    // translate, scale and rotate, each checked by volume_transform_problem on its own so that the
    // message points at the key that is wrong; the transform's rules live in one place.
    VolumeTransform volume_transform(const toml::table& t, const KeyPath& path) const {
        VolumeTransform result;
        const auto check = [&](const toml::node& n, std::string_view key, const VolumeTransform& alone) {
            const std::string problem = volume_transform_problem(alone);
            if (!problem.empty()) fail(n, path / key, problem);
        };
        if (const toml::node* n = t.get("translate")) {
            VolumeTransform alone;
            alone.translate = vec3(*n, path / "translate").v;
            check(*n, "translate", alone);
            result.translate = alone.translate;
        }
        if (const toml::node* n = t.get("scale")) {
            VolumeTransform alone;
            alone.scale = number(*n, path / "scale");
            check(*n, "scale", alone);
            result.scale = alone.scale;
        }
        if (const toml::node* n = t.get("rotate")) {
            VolumeTransform alone;
            alone.rotate_deg = vec3(*n, path / "rotate").v;
            check(*n, "rotate", alone);
            result.rotate_deg = alone.rotate_deg;
        }
        return result;
    }

    // --- Preset sections -------------------------------------------------------------------------

    void preset(const toml::node& node, const KeyPath& path, Preset& p) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kPresetKeys);
        if (const toml::node* n = t.get("name")) {
            const KeyPath np = path / "name";
            p.name = one_line(*n, np);
            // The name names output files (`brume play` writes NAME.0001.png): no paths, no hidden files.
            const bool ok = !p.name.empty() && p.name[0] != '.' &&
                            std::all_of(p.name.begin(), p.name.end(), [](char c) {
                                return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                                       c == '-' || c == '_' || c == '.';
                            });
            if (!ok)
                fail(*n, np,
                     "must be letters, digits, '-', '_' and '.', not starting with '.' (it names output files; got " +
                         toml_text::quoted(p.name) + ")");
        }
        if (const toml::node* n = t.get("description")) p.description = one_line(*n, path / "description");
    }

    void timeline(const toml::node& node, const KeyPath& path, Timeline& tl, Camera& camera) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kTimelineKeys);
        const toml::node* fps = t.get("fps");
        const toml::node* duration = t.get("duration");
        if (fps) tl.fps = in_interval(*fps, path / "fps", 0.0, kMaxFps, true, " frames per second");
        if (duration)
            tl.duration = in_interval(*duration, path / "duration", 0.0, kMaxDurationSeconds, true, " seconds");
        if (const toml::node* n = t.get("substeps"))
            tl.substeps = int(integer_in(*n, path / "substeps", 1, kMaxSubsteps));
        if (const toml::node* n = t.get("preroll"))
            tl.preroll = in_interval(*n, path / "preroll", 0.0, kMaxDurationSeconds, false, " seconds");
        if (const toml::node* n = t.get("seed"))
            tl.seed = std::uint64_t(integer_in(*n, path / "seed", 0, std::numeric_limits<std::int64_t>::max()));
        if (const toml::node* n = t.get("max_particles"))
            tl.max_particles = std::uint32_t(integer_in(*n, path / "max_particles", 1, kMaxParticles));
        if (const toml::node* n = t.get("resolution")) {
            const KeyPath p = path / "resolution";
            const toml::array* a = n->as_array();
            if (!a || a->size() != 2) fail(*n, p, "must be [width, height] (got " + describe(*n) + ")");
            camera.width = int(integer_in((*a)[0], p[0], 1, kMaxImageSide));
            camera.height = int(integer_in((*a)[1], p[1], 1, kMaxImageSide));
        }
        if (tl.frame_count() < 1)  // both defaults give frames, so one of the two is present
            fail(*last_of({fps, duration}), path / (last_of({fps, duration}) == duration ? "duration" : "fps"),
                 "duration * fps gives no frame (got " + shortest(tl.duration) + " s at " + shortest(tl.fps) + " fps)");
    }

    void emitters(const toml::node& node, const KeyPath& array_path, std::vector<EmitterDesc>& out) const {
        const toml::array& a = table_array(node, array_path, kMaxEmitters, "emitters");
        out.resize(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) emitter(*a[i].as_table(), array_path[i], out[i]);
    }

    void emitter(const toml::table& t, const KeyPath& path, EmitterDesc& e) const {
        if (const toml::node* n = t.get("shape")) e.shape = EmitterShape(choice(*n, path / "shape", kShapeNames));
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
        check_keys(t, path, allowed, kEmitterKeys, [&](std::string_view key) {
            return "not used by shape " + toml_text::quoted(shape_name) + " (it is for shape " + users(key) + ")";
        });

        if (const toml::node* n = t.get("name")) e.name = one_line(*n, path / "name");
        if (const toml::node* n = t.get("center")) e.center = coordinates(*n, path / "center");
        if (e.shape == EmitterShape::Density) {
            density_source(t, path, "a \"density\" emitter needs file", e.density_source);
            e.density_transform = volume_transform(t, path);
        }
        const std::string needs = "a " + toml_text::quoted(shape_name) + " emitter needs " +
                                  (e.shape == EmitterShape::Box ? "half_extent" : "radius");
        if (e.shape == EmitterShape::Sphere || e.shape == EmitterShape::Disc)
            e.radius = positive(required(t, "radius", path, needs), path / "radius", kMaxCoordinate);
        if (e.shape == EmitterShape::Box) {
            const KeyPath p = path / "half_extent";
            const Vec3Field f = vec3(required(t, "half_extent", path, needs), p);
            each(f, p, [](double v) { return v >= 0.0; }, "must not be negative");
            each(f, p, [](double v) { return v <= kMaxCoordinate; }, "absurd size: must be at most 1e7");
            e.half_extent = f.v;
        }
        if (const toml::node* n = t.get("normal")) e.normal = direction(*n, path / "normal");

        if (const toml::node* n = t.get("rate")) e.rate = non_negative(*n, path / "rate", kMaxEmissionRate);
        const toml::node* start = t.get("start");
        const toml::node* stop = t.get("stop");
        // Times are seconds on the simulation clock (sim/simulator.h), which starts at 0 with the preroll.
        if (start) e.start = time(*start, path / "start");
        if (stop) {
            const KeyPath p = path / "stop";
            e.stop = time(*stop, p);
            if (!(e.stop >= e.start))
                fail(*last_of({start, stop}), p,
                     "must not be before start (got stop " + shortest(e.stop) + ", start " + shortest(e.start) + ")");
        }
        if (const toml::node* n = t.get("bursts")) bursts(*n, path / "bursts", e.bursts);

        if (const toml::node* n = t.get("direction")) e.direction = direction(*n, path / "direction");
        if (const toml::node* n = t.get("speed"))
            e.speed = range(*n, path / "speed", [&](const toml::node& v, const KeyPath& p) {
                return non_negative(v, p, kMaxForce);
            });
        if (const toml::node* n = t.get("cone_deg"))
            e.cone_deg = in_interval(*n, path / "cone_deg", 0.0, 180.0, false, " degrees");
        if (const toml::node* n = t.get("jitter")) e.jitter = non_negative(*n, path / "jitter", kMaxForce);
        if (const toml::node* n = t.get("lifetime"))
            e.lifetime = range(*n, path / "lifetime", [&](const toml::node& v, const KeyPath& p) {
                return positive(v, p, kMaxTimeSeconds);
            });
        if (const toml::node* n = t.get("particle_radius"))
            e.radius_range = range(*n, path / "particle_radius", [&](const toml::node& v, const KeyPath& p) {
                return positive(v, p, kMaxCoordinate);
            });
        if (const toml::node* n = t.get("extinction"))
            e.extinction = range(*n, path / "extinction", [&](const toml::node& v, const KeyPath& p) {
                return non_negative(v, p, kMaxExtinction);
            });
        if (const toml::node* n = t.get("albedo")) e.albedo = color_range(*n, path / "albedo");
        if (const toml::node* n = t.get("curves")) curves(*n, path / "curves", e.albedo.max, e.curves);
    }

    void bursts(const toml::node& node, const KeyPath& array_path, std::vector<EmitterDesc::Burst>& out) const {
        const toml::array& a =
            inline_table_array(node, array_path, kMaxListEntries, "bursts", "[{ time = 0.5, count = 200 }]");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const KeyPath path = array_path[i];
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kBurstKeys);
            const std::string_view needs = "each burst needs time and count";
            EmitterDesc::Burst b;
            b.time = time(required(t, "time", path, needs), path / "time");
            b.count = std::uint32_t(integer_in(required(t, "count", path, needs), path / "count", 0, kMaxBurstCount));
            out.push_back(b);
        }
    }

    void curves(const toml::node& node, const KeyPath& path, const glm::dvec3& albedo_max, AgeCurves& c) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kCurveKeys);
        if (const toml::node* n = t.get("radius_growth"))
            c.radius_growth = non_negative(*n, path / "radius_growth", 1e6);  // a million-fold growth is a typo
        const toml::node* fade_in = t.get("fade_in");
        const toml::node* fade_out = t.get("fade_out");
        if (fade_in) c.fade_in = in_interval(*fade_in, path / "fade_in", 0.0, 1.0, false);
        if (fade_out) c.fade_out = in_interval(*fade_out, path / "fade_out", 0.0, 1.0, false);
        if (!(c.fade_in + c.fade_out <= 1.0)) {
            const toml::node* last = last_of({fade_in, fade_out});
            fail(*last, path / (last == fade_out ? "fade_out" : "fade_in"),
                 "fade_in + fade_out must not exceed 1 (got " + shortest(c.fade_in) + " + " +
                     shortest(c.fade_out) + ")");
        }
        if (const toml::node* n = t.get("albedo_ramp"))
            albedo_ramp(*n, path / "albedo_ramp", albedo_max, c.albedo_ramp);
    }

    void albedo_ramp(const toml::node& node, const KeyPath& array_path, const glm::dvec3& albedo_max,
                     std::vector<AgeCurves::AlbedoKey>& out) const {
        const toml::array& a = inline_table_array(node, array_path, kMaxListEntries, "albedo_ramp keys",
                                                  "[{ age = 0.0, multiplier = [1, 1, 1] }]");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const KeyPath path = array_path[i];
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kRampKeys);
            const std::string_view needs = "each albedo_ramp key needs age and multiplier";
            AgeCurves::AlbedoKey k;
            const toml::node& age = required(t, "age", path, needs);
            const KeyPath age_path = path / "age";
            k.age = in_interval(age, age_path, 0.0, 1.0, false);
            if (i > 0 && !(k.age > out.back().age))
                fail(age, age_path,
                     "must be greater than the previous key's age (got " + shortest(k.age) + " after " +
                         shortest(out.back().age) + ")");
            const KeyPath mp = path / "multiplier";
            const Vec3Field m = vec3(required(t, "multiplier", path, needs), mp);
            each(m, mp, [](double v) { return v >= 0.0; }, "must not be negative");
            // The multiplied albedo stays a physical albedo: a medium cannot scatter more than it removes.
            for (std::size_t c = 0; c < 3; ++c) {
                const int ci = static_cast<int>(c);
                if (!(albedo_max[ci] * m.v[ci] <= 1.0))
                    fail(*m.elems[c], mp[c],
                         "makes the albedo exceed 1 (albedo max " + shortest(albedo_max[ci]) + " * " +
                             shortest(m.v[ci]) + " = " + shortest(albedo_max[ci] * m.v[ci]) + ")");
            }
            k.multiplier = m.v;
            out.push_back(k);
        }
    }

    void forces(const toml::node& node, const KeyPath& array_path, std::vector<ForceDesc>& out) const {
        const toml::array& a = table_array(node, array_path, kMaxForces, "forces");
        out.resize(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) force(*a[i].as_table(), array_path[i], out[i]);
    }

    void force(const toml::table& t, const KeyPath& path, ForceDesc& f) const {
        const std::string types = "each [[force]] needs type, one of " + join(kForceNames);
        f.kind = ForceKind(choice(required(t, "type", path, types), path / "type", kForceNames));
        const std::string_view type = kForceNames[std::size_t(f.kind)];
        const std::span<const std::string_view> own = force_keys(f.kind);
        std::vector<std::string_view> allowed{"type"};
        allowed.insert(allowed.end(), own.begin(), own.end());
        check_keys(t, path, allowed, kForceKeys, [&](std::string_view) {
            return "not used by type " + toml_text::quoted(type) + " (" + std::string(type) + " takes " +
                   join(own) + ")";
        });
        const std::string needs = "a " + toml_text::quoted(type) + " force needs " + join(own);
        switch (f.kind) {
            case ForceKind::Gravity:
                f.vector = force_vector(required(t, "vector", path, needs), path / "vector");
                break;
            case ForceKind::Buoyancy:  // negative: a medium denser than the air around it sinks
                f.strength = bounded(required(t, "strength", path, needs), path / "strength", kMaxForce);
                break;
            case ForceKind::Wind:  // a drag toward the wind's velocity: a negative rate would pump energy in
                f.vector = force_vector(required(t, "vector", path, needs), path / "vector");
                f.strength = non_negative(required(t, "strength", path, needs), path / "strength", kMaxForce);
                break;
            case ForceKind::Drag:
                f.strength = non_negative(required(t, "strength", path, needs), path / "strength", kMaxForce);
                break;
            case ForceKind::Turbulence:
                f.strength = non_negative(required(t, "strength", path, "a \"turbulence\" force needs strength"),
                                          path / "strength", kMaxForce);
                if (const toml::node* n = t.get("scale")) f.scale = positive(*n, path / "scale", kMaxForce);
                if (const toml::node* n = t.get("speed")) f.speed = non_negative(*n, path / "speed", kMaxForce);
                if (const toml::node* n = t.get("octaves")) f.octaves = int(integer_in(*n, path / "octaves", 1, 16));
                if (const toml::node* n = t.get("lacunarity"))
                    f.lacunarity = in_interval(*n, path / "lacunarity", 1.0, 16.0, false);
                if (const toml::node* n = t.get("gain")) f.gain = in_interval(*n, path / "gain", 0.0, 1.0, false);
                break;
            case ForceKind::Vortex:  // the sign of strength is the sense of rotation about axis
                f.strength = bounded(required(t, "strength", path, "a \"vortex\" force needs strength"),
                                     path / "strength", kMaxForce);
                if (const toml::node* n = t.get("center")) f.center = coordinates(*n, path / "center");
                if (const toml::node* n = t.get("axis")) f.axis = direction(*n, path / "axis");
                if (const toml::node* n = t.get("radius")) f.radius = positive(*n, path / "radius", kMaxCoordinate);
                break;
        }
    }

    void camera_path(const toml::node& node, const KeyPath& path, const Camera& camera, CameraPath& cp) const {
        const toml::table& t = table(node, path);
        const std::string types = "[camera_path] needs type, one of " + join(kCameraPathNames);
        cp.kind = CameraPath::Kind(choice(required(t, "type", path, types), path / "type", kCameraPathNames));
        const std::string_view type = kCameraPathNames[std::size_t(cp.kind)];
        const std::span<const std::string_view> own = camera_path_keys(cp.kind);
        std::vector<std::string_view> allowed{"type"};
        allowed.insert(allowed.end(), own.begin(), own.end());
        check_keys(t, path, allowed, kCameraPathKeys, [&](std::string_view) {
            return "not used by type " + toml_text::quoted(type) +
                   (own.empty() ? std::string(" (it takes no other key)")
                                : " (" + std::string(type) + " takes " + join(own) + ")");
        });
        switch (cp.kind) {
            case CameraPath::Kind::Static: break;
            case CameraPath::Kind::Keyframes:
                camera_keys(required(t, "keys", path, "a \"keyframes\" path needs keys"), path / "keys", camera,
                            cp.keys);
                break;
            case CameraPath::Kind::Orbit: {
                if (const toml::node* n = t.get("center")) cp.orbit_center = coordinates(*n, path / "center");
                // The eye circles at `radius` around the vertical axis, looking at center: radius 0
                // would look straight down the axis, parallel to a vertical up.
                if (const toml::node* n = t.get("radius"))
                    cp.orbit_radius = positive(*n, path / "radius", kMaxCoordinate);
                if (const toml::node* n = t.get("height"))
                    cp.orbit_height = bounded(*n, path / "height", kMaxCoordinate);
                if (const toml::node* n = t.get("start_deg"))
                    cp.orbit_start_deg = bounded(*n, path / "start_deg", kMaxTimeSeconds);
                if (const toml::node* n = t.get("deg_per_second"))
                    cp.orbit_deg_per_second = bounded(*n, path / "deg_per_second", kMaxTimeSeconds);
                break;
            }
        }
    }

    void camera_keys(const toml::node& node, const KeyPath& array_path, const Camera& camera,
                     std::vector<CameraKey>& out) const {
        const toml::array& a = inline_table_array(node, array_path, kMaxListEntries, "camera keys",
                                                  "[{ time = 0.0, position = [0, 1, 6], look_at = [0, 1, 0] }]");
        if (a.size() < 2)
            fail(node, array_path, "needs at least 2 keys (got " + std::to_string(a.size()) + ")");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const KeyPath path = array_path[i];
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kCameraKeyKeys);
            const std::string_view needs = "each camera key needs time, position, look_at";
            CameraKey k;
            const toml::node& key_time = required(t, "time", path, needs);
            const KeyPath time_path = path / "time";
            k.time = this->time(key_time, time_path);
            if (i > 0 && !(k.time > out.back().time))
                fail(key_time, time_path,
                     "must be later than the previous key's time (got " + shortest(k.time) + " after " +
                         shortest(out.back().time) + ")");
            k.position = coordinates(required(t, "position", path, needs), path / "position");
            const toml::node& look_at = required(t, "look_at", path, needs);
            const KeyPath look_path = path / "look_at";
            k.look_at = coordinates(look_at, look_path);
            check_view(look_at.source(), look_path, k.position, k.look_at, camera.up,
                       "must differ from position (they are the same point)");
            out.push_back(k);
        }
    }

    void render_settings(const toml::node& node, const KeyPath& path, RenderSettingsPreset& r) const {
        const toml::table& t = table(node, path);
        check_keys(t, path, kRenderSettingsKeys);
        if (const toml::node* n = t.get("method"))
            r.method = std::string(kMethodNames[choice(*n, path / "method", kMethodNames)]);
        if (const toml::node* n = t.get("exposure"))
            r.exposure = in_interval(*n, path / "exposure", -kMaxExposureStops, kMaxExposureStops, false, " stops");
    }

    const std::string& file_;
    DocumentKind kind_;
};

// --- Writing ----------------------------------------------------------------------------------------

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

Preset parse_toml_document(std::string_view text, const std::string& source_name, DocumentKind kind) {
    toml::table root;
    try {
        root = toml::parse(text, std::string_view(source_name));
    } catch (const toml::parse_error& e) {
        throw SceneFileError(source_name, static_cast<int>(e.source().begin.line),
                             static_cast<int>(e.source().begin.column), "",
                             "invalid TOML: " + std::string(e.description()));
    }
    return Parser(source_name, kind).document(root);
}

Preset parse_preset_toml(std::string_view text, const std::string& source_name) {
    return parse_toml_document(text, source_name, DocumentKind::Preset);
}

Preset load_preset_file(const std::filesystem::path& path) {
    Preset p = parse_preset_toml(toml_text::read_file(path), path.string());
    // Relative grid files are found beside the preset, wherever it is run from.
    const std::string dir = path.parent_path().string();
    for (VdbVolume& v : p.scene.volumes) v.source.base_dir = dir;
    for (EmitterDesc& e : p.emitters)
        if (e.shape == EmitterShape::Density) e.density_source.base_dir = dir;
    return p;
}

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
