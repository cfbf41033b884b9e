#include "sim/scene_file.h"

#include <glm/geometric.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
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

// Shortest text that reads back to the same double (std::to_chars guarantees the round trip).
void append_double(std::string& out, double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

std::string fmt(double v) {
    std::string s;
    append_double(s, v);
    return s;
}

// As append_double, but always a TOML float ("1.0", not "1"), so written files keep their types.
void append_toml_double(std::string& out, double v) {
    const std::size_t start = out.size();
    append_double(out, v);
    if (out.find_first_of(".en", start) == std::string::npos) out += ".0";  // 'n': nan, inf
}

// Text from the file is printed quoted and escaped, so a message stays one readable line.
std::string quote(std::string_view s) {
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

// Keys are printed bare when TOML would allow them bare.
std::string quote_key(std::string_view k) {
    const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
               c == '-';
    });
    return bare ? std::string(k) : quote(k);
}

// A key path, formatted only when an error needs it: parsing a million spheres builds no strings.
struct KeyPath {
    std::string_view table;       // "camera", "sphere", ...; empty at the top level
    std::ptrdiff_t index = -1;    // element of an array of tables
    std::string_view key;         // used when has_key (a key may be the empty string "")
    bool has_key = false;
    int component = -1;           // element of a 3-vector

    KeyPath with_key(std::string_view k) const {
        KeyPath p = *this;
        p.key = k;
        p.has_key = true;
        return p;
    }
    KeyPath with_component(int c) const {
        KeyPath p = *this;
        p.component = c;
        return p;
    }
    std::string str() const {
        std::string s = table.empty() ? std::string() : quote_key(table);
        if (index >= 0) s += '[' + std::to_string(index) + ']';
        if (has_key) {
            if (!s.empty()) s += '.';
            s += quote_key(key);
        }
        if (component >= 0) s += '[' + std::to_string(component) + ']';
        return s;
    }
};

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

std::optional<std::string_view> suggest(std::string_view unknown, std::span<const std::string_view> known) {
    std::optional<std::string_view> best;
    std::size_t best_distance = 3;  // suggest only within distance 2
    for (const std::string_view k : known) {
        const std::size_t dist = edit_distance(unknown, k);
        if (dist < best_distance) {
            best = k;
            best_distance = dist;
        }
    }
    return best;
}

std::string join(std::span<const std::string_view> names) {
    std::string s;
    for (const std::string_view n : names) {
        if (!s.empty()) s += ", ";
        s += n;
    }
    return s;
}

// The schema, in the order keys are checked and written.
constexpr std::array<std::string_view, 5> kRootKeys{"camera", "lighting", "render", "box", "sphere"};
constexpr std::array<std::string_view, 6> kCameraKeys{"position", "look_at", "up", "fov_y_deg", "width", "height"};
constexpr std::array<std::string_view, 4> kLightingKeys{"ambient", "sun", "sun_direction", "background"};
constexpr std::array<std::string_view, 1> kRenderKeys{"min_transmittance"};
constexpr std::array<std::string_view, 3> kBoxKeys{"min", "max", "radiance"};
constexpr std::array<std::string_view, 4> kSphereKeys{"center", "radius", "extinction", "albedo"};

std::string describe(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array of " + std::to_string(n.as_array()->size()) + " element(s)";
        case toml::node_type::string: {
            const std::string_view v = n.as_string()->get();
            return "a string " + quote(v.substr(0, 40)) + (v.size() > 40 ? "..." : "");
        }
        case toml::node_type::integer: return "an integer " + std::to_string(n.as_integer()->get());
        case toml::node_type::floating_point: {
            std::string s = "a floating-point number ";
            append_toml_double(s, n.as_floating_point()->get());
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
    explicit Parser(const std::string& file) : file_(file) {}

    Scene scene(const toml::table& root) const {
        Scene s;
        check_root_keys(root);
        if (const toml::node* n = root.get("camera")) camera(*n, s.camera);
        if (const toml::node* n = root.get("lighting")) lighting(*n, s.lighting);
        if (const toml::node* n = root.get("render")) render(*n, s.render);
        if (const toml::node* n = root.get("box")) boxes(*n, s.boxes);
        if (const toml::node* n = root.get("sphere")) spheres(*n, s.spheres);
        s.source = file_;
        return s;
    }

private:
    [[noreturn]] void fail(const toml::source_region& where, const KeyPath& path, const std::string& problem) const {
        throw SceneFileError(file_, static_cast<int>(where.begin.line), 0, path.str(), problem);
    }
    [[noreturn]] void fail(const toml::node& n, const KeyPath& path, const std::string& problem) const {
        fail(n.source(), path, problem);
    }

    // Reports the unknown key that comes first in the file, with a suggestion when one is close.
    void check_keys(const toml::table& t, const KeyPath& table_path, std::span<const std::string_view> known) const {
        const toml::key* first = nullptr;
        for (auto&& [k, v] : t) {
            if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
            if (!first || k.source().begin < first->source().begin) first = &k;
        }
        if (!first) return;
        std::string problem = unknown_what(t.at(first->str()));
        if (const auto s = suggest(first->str(), known))
            problem += " (did you mean \"" + std::string(*s) + "\"?)";
        else
            problem += " (allowed here: " + join(known) + ")";
        fail(first->source(), table_path.with_key(first->str()), problem);
    }

    // At the top level a misplaced section key ("width" above [camera]) gets pointed to its section.
    void check_root_keys(const toml::table& root) const {
        const toml::key* first = nullptr;
        for (auto&& [k, v] : root) {
            if (std::find(kRootKeys.begin(), kRootKeys.end(), k.str()) != kRootKeys.end()) continue;
            if (!first || k.source().begin < first->source().begin) first = &k;
        }
        if (!first) return;
        const std::string_view name = first->str();
        std::string problem = unknown_what(root.at(name));
        const auto in = [&](std::span<const std::string_view> keys) {
            return std::find(keys.begin(), keys.end(), name) != keys.end();
        };
        if (const auto s = suggest(name, kRootKeys))
            problem += " (did you mean \"" + std::string(*s) + "\"?)";
        else if (in(kCameraKeys))
            problem += " (it belongs under [camera])";
        else if (in(kLightingKeys))
            problem += " (it belongs under [lighting])";
        else if (in(kRenderKeys))
            problem += " (it belongs under [render])";
        else if (in(kBoxKeys))
            problem += " (it belongs in a [[box]] section)";
        else if (in(kSphereKeys))
            problem += " (it belongs in a [[sphere]] section)";
        else
            problem += " (allowed at the top level: " + join(kRootKeys) + ")";
        fail(first->source(), KeyPath{}.with_key(name), problem);
    }

    const toml::table& table(const toml::node& n, const KeyPath& path) const {
        const toml::table* t = n.as_table();
        if (!t) fail(n, path, "must be a table (got " + describe(n) + ")");
        return *t;
    }

    // Each element of an array of tables, checked to be a table and counted against a limit.
    const toml::array& table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                   const char* what) const {
        const std::string header = "[[" + std::string(path.table) + "]]";
        const toml::array* a = n.as_array();
        if (!a) {
            std::string problem = "must be an array of tables (got " + describe(n) + ")";
            if (n.is_table()) problem += ": write " + header + ", not [" + std::string(path.table) + "]";
            else problem += ": write each as a " + header + " section";
            fail(n, path, problem);
        }
        if (a->size() > limit)
            fail(n, path,
                 "absurd size: too many " + std::string(what) + " (got " + std::to_string(a->size()) +
                     ", the limit is " + std::to_string(limit) + ")");
        for (std::size_t i = 0; i < a->size(); ++i) {
            KeyPath p = path;
            p.index = static_cast<std::ptrdiff_t>(i);
            if (!(*a)[i].is_table()) fail((*a)[i], p, "must be a table (got " + describe((*a)[i]) + ")");
        }
        return *a;
    }

    const toml::node& required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                               std::span<const std::string_view> all) const {
        const toml::node* n = t.get(key);
        if (!n)
            fail(t.source(), table_path.with_key(key),
                 "missing (each [[" + std::string(table_path.table) + "]] needs " + join(all) + ")");
        return *n;
    }

    // Integers are accepted where floats are expected; NaN and Inf never are.
    double number(const toml::node& n, const KeyPath& path) const {
        double v = 0.0;
        if (const auto* i = n.as_integer())
            v = static_cast<double>(i->get());
        else if (const auto* f = n.as_floating_point())
            v = f->get();
        else
            fail(n, path, "must be a number (got " + describe(n) + ")");
        if (!std::isfinite(v)) fail(n, path, "must be finite (got " + fmt(v) + ")");
        return v;
    }

    int integer_in(const toml::node& n, const KeyPath& path, int lo, int hi) const {
        const auto* i = n.as_integer();
        if (!i) fail(n, path, "must be an integer (got " + describe(n) + ")");
        const std::int64_t v = i->get();
        if (v < lo || v > hi)
            fail(n, path,
                 "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " +
                     std::to_string(v) + ")");
        return static_cast<int>(v);
    }

    Vec3Field vec3(const toml::node& n, const KeyPath& path) const {
        const toml::array* a = n.as_array();
        if (!a) fail(n, path, "must be an array of 3 numbers (got " + describe(n) + ")");
        if (a->size() != 3)
            fail(n, path, "must be an array of exactly 3 numbers (got " + std::to_string(a->size()) + ")");
        Vec3Field f;
        for (int c = 0; c < 3; ++c) {
            f.elems[c] = &(*a)[static_cast<std::size_t>(c)];
            f.v[c] = number(*f.elems[c], path.with_component(c));
        }
        return f;
    }

    template <class Ok>
    void each(const Vec3Field& f, const KeyPath& path, Ok ok, const char* rule) const {
        for (int c = 0; c < 3; ++c)
            if (!ok(f.v[c]))
                fail(*f.elems[c], path.with_component(c), std::string(rule) + " (got " + fmt(f.v[c]) + ")");
    }

    // A position or direction: bounded so that squaring it (lengths, intersections) stays finite.
    glm::dvec3 coordinates(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return std::abs(v) <= kMaxCoordinate; },
             "absurd size: coordinates must be within 1e7 of the origin");
        return f.v;
    }

    glm::dvec3 radiance(const toml::node& n, const KeyPath& path) const {
        const Vec3Field f = vec3(n, path);
        each(f, path, [](double v) { return v >= 0.0; }, "must not be negative");
        each(f, path, [](double v) { return v <= kMaxRadiance; }, "absurd size: must be at most 1e9");
        return f.v;
    }

    // The line of the last present key among candidates, else the table's: where a cross-key error points.
    static const toml::source_region& where(const toml::table& t, std::initializer_list<const toml::node*> nodes) {
        const toml::source_region* r = &t.source();
        for (const toml::node* n : nodes)
            if (n && (r == &t.source() || r->begin < n->source().begin)) r = &n->source();
        return *r;
    }

    void camera(const toml::node& node, Camera& c) const {
        const KeyPath path{"camera"};
        const toml::table& t = table(node, path);
        check_keys(t, path, kCameraKeys);
        const toml::node* position = t.get("position");
        const toml::node* look_at = t.get("look_at");
        const toml::node* up = t.get("up");
        if (position) c.position = coordinates(*position, path.with_key("position"));
        if (look_at) c.look_at = coordinates(*look_at, path.with_key("look_at"));
        if (up) c.up = coordinates(*up, path.with_key("up"));
        if (const toml::node* n = t.get("fov_y_deg")) {
            const KeyPath p = path.with_key("fov_y_deg");
            c.fov_y_deg = number(*n, p);
            if (!(c.fov_y_deg > 0.0 && c.fov_y_deg <= kMaxFovYDeg))
                fail(*n, p, "must be in (0, 179] degrees (got " + fmt(c.fov_y_deg) + ")");
        }
        if (const toml::node* n = t.get("width")) c.width = integer_in(*n, path.with_key("width"), 1, kMaxImageSide);
        if (const toml::node* n = t.get("height"))
            c.height = integer_in(*n, path.with_key("height"), 1, kMaxImageSide);

        // make_camera_rays normalises look_at - position and cross(forward, up): both must be well defined.
        const glm::dvec3 view = c.look_at - c.position;
        const double view_length = glm::length(view);
        if (!(view_length > 0.0))
            fail(where(t, {position, look_at}), path.with_key(look_at ? "look_at" : "position"),
                 "position and look_at must differ (they are the same point)");
        const double up_length = glm::length(c.up);
        if (!(up_length > 0.0)) fail(where(t, {up}), path.with_key("up"), "must not be zero");
        // sin(angle) below 1e-9 leaves the basis ill-conditioned; the camera has no defined roll.
        const double sin_angle = glm::length(glm::cross(view / view_length, c.up / up_length));
        if (!(sin_angle > 1e-9))
            fail(where(t, {position, look_at, up}), path.with_key("up"),
                 "must not be parallel to the view direction (look_at - position)");
    }

    void lighting(const toml::node& node, Lighting& l) const {
        const KeyPath path{"lighting"};
        const toml::table& t = table(node, path);
        check_keys(t, path, kLightingKeys);
        if (const toml::node* n = t.get("ambient")) l.ambient = radiance(*n, path.with_key("ambient"));
        if (const toml::node* n = t.get("sun")) l.sun = radiance(*n, path.with_key("sun"));
        if (const toml::node* n = t.get("sun_direction")) {
            const KeyPath p = path.with_key("sun_direction");
            l.sun_direction = coordinates(*n, p);
            if (!(glm::length(l.sun_direction) > 0.0)) fail(*n, p, "must not be zero (it is normalised)");
        }
        if (const toml::node* n = t.get("background")) l.background = radiance(*n, path.with_key("background"));
    }

    void render(const toml::node& node, RenderSettings& r) const {
        const KeyPath path{"render"};
        const toml::table& t = table(node, path);
        check_keys(t, path, kRenderKeys);
        if (const toml::node* n = t.get("min_transmittance")) {
            const KeyPath p = path.with_key("min_transmittance");
            r.min_transmittance = number(*n, p);
            if (!(r.min_transmittance >= 0.0 && r.min_transmittance < 1.0))
                fail(*n, p, "must be in [0, 1) (got " + fmt(r.min_transmittance) + ")");
        }
    }

    void boxes(const toml::node& node, std::vector<Box>& out) const {
        const KeyPath array_path{"box"};
        const toml::array& a = table_array(node, array_path, kMaxBoxes, "boxes");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            KeyPath path = array_path;
            path.index = static_cast<std::ptrdiff_t>(i);
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kBoxKeys);
            Box b;
            b.min = coordinates(required(t, "min", path, kBoxKeys), path.with_key("min"));
            const toml::node& max = required(t, "max", path, kBoxKeys);
            b.max = coordinates(max, path.with_key("max"));
            b.radiance = radiance(required(t, "radiance", path, kBoxKeys), path.with_key("radiance"));
            for (int c = 0; c < 3; ++c) {
                if (!(b.min[c] < b.max[c])) {
                    const char axis = "xyz"[c];
                    fail(max, path.with_key("max"),
                         std::string("must exceed min on every axis (max.") + axis + " = " + fmt(b.max[c]) +
                             ", min." + axis + " = " + fmt(b.min[c]) + ")");
                }
            }
            out.push_back(b);
        }
    }

    void spheres(const toml::node& node, std::vector<Sphere>& out) const {
        const KeyPath array_path{"sphere"};
        const toml::array& a = table_array(node, array_path, kMaxSpheres, "spheres");
        out.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            KeyPath path = array_path;
            path.index = static_cast<std::ptrdiff_t>(i);
            const toml::table& t = *a[i].as_table();
            check_keys(t, path, kSphereKeys);
            Sphere s;
            s.center = coordinates(required(t, "center", path, kSphereKeys), path.with_key("center"));
            {
                const toml::node& n = required(t, "radius", path, kSphereKeys);
                const KeyPath p = path.with_key("radius");
                s.radius = number(n, p);
                if (!(s.radius > 0.0)) fail(n, p, "must be positive and finite (got " + fmt(s.radius) + ")");
                if (!(s.radius <= kMaxCoordinate))
                    fail(n, p, "absurd size: must be at most 1e7 (got " + fmt(s.radius) + ")");
            }
            {
                const toml::node& n = required(t, "extinction", path, kSphereKeys);
                const KeyPath p = path.with_key("extinction");
                s.extinction = number(n, p);
                if (!(s.extinction >= 0.0)) fail(n, p, "must not be negative (got " + fmt(s.extinction) + ")");
                if (!(s.extinction <= kMaxExtinction))
                    fail(n, p, "absurd size: must be at most 1e9 (got " + fmt(s.extinction) + ")");
            }
            {
                const KeyPath p = path.with_key("albedo");
                const Vec3Field f = vec3(required(t, "albedo", path, kSphereKeys), p);
                each(f, p, [](double v) { return v >= 0.0 && v <= 1.0; }, "must be in [0, 1]");
                s.albedo = f.v;
            }
            out.push_back(s);
        }
    }

    const std::string& file_;
};

void append_vec3(std::string& out, std::string_view key, const glm::dvec3& v) {
    out += key;
    out += " = [";
    for (int c = 0; c < 3; ++c) {
        if (c) out += ", ";
        append_toml_double(out, v[c]);
    }
    out += "]\n";
}

void append_number(std::string& out, std::string_view key, double v) {
    out += key;
    out += " = ";
    append_toml_double(out, v);
    out += '\n';
}

}  // namespace

SceneFileError::SceneFileError(std::string file, int line, int column, std::string key_path, std::string problem)
    : std::runtime_error(format_message(file, line, column, key_path, problem)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_path_(std::move(key_path)),
      problem_(std::move(problem)) {}

Scene parse_scene_toml(std::string_view text, const std::string& source_name) {
    toml::table root;
    try {
        root = toml::parse(text, std::string_view(source_name));
    } catch (const toml::parse_error& e) {
        throw SceneFileError(source_name, static_cast<int>(e.source().begin.line),
                             static_cast<int>(e.source().begin.column), "",
                             "invalid TOML: " + std::string(e.description()));
    }
    return Parser(source_name).scene(root);
}

Scene load_scene_file(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw SceneFileError(name, 0, 0, "", "cannot read: is a directory");
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) {
        const int err = errno;
        throw SceneFileError(name, 0, 0, "", "cannot open: " + std::generic_category().message(err));
    }
    std::string text;
    char buf[1 << 16];
    std::size_t got = 0;
    while ((got = std::fread(buf, 1, sizeof buf, f.get())) > 0) text.append(buf, got);
    if (std::ferror(f.get())) {
        const int err = errno;
        throw SceneFileError(name, 0, 0, "", "cannot read: " + std::generic_category().message(err));
    }
    return parse_scene_toml(text, name);
}

std::string scene_to_toml(const Scene& scene) {
    std::string out;
    out.reserve(1024 + scene.boxes.size() * 128 + scene.spheres.size() * 160);
    out += "# Brume scene (schema: sim/scene_file.h)\n";

    const Camera& c = scene.camera;
    out += "\n[camera]\n";
    append_vec3(out, "position", c.position);
    append_vec3(out, "look_at", c.look_at);
    append_vec3(out, "up", c.up);
    append_number(out, "fov_y_deg", c.fov_y_deg);
    out += "width = " + std::to_string(c.width) + '\n';
    out += "height = " + std::to_string(c.height) + '\n';

    const Lighting& l = scene.lighting;
    out += "\n[lighting]\n";
    append_vec3(out, "ambient", l.ambient);
    append_vec3(out, "sun", l.sun);
    append_vec3(out, "sun_direction", l.sun_direction);
    append_vec3(out, "background", l.background);

    out += "\n[render]\n";
    append_number(out, "min_transmittance", scene.render.min_transmittance);

    for (const Box& b : scene.boxes) {
        out += "\n[[box]]\n";
        append_vec3(out, "min", b.min);
        append_vec3(out, "max", b.max);
        append_vec3(out, "radiance", b.radiance);
    }
    for (const Sphere& s : scene.spheres) {
        out += "\n[[sphere]]\n";
        append_vec3(out, "center", s.center);
        append_number(out, "radius", s.radius);
        append_number(out, "extinction", s.extinction);
        append_vec3(out, "albedo", s.albedo);
    }
    return out;
}

}  // namespace brume
