// The TOML reading toolkit (sim/toml_reader.h): key paths, typed readers and unknown-key checks, apart
// from any section so that the scene and preset readers share one copy of every rule and message.
#include "sim/toml_reader.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace brume::toml_read {

using toml_text::shortest;
using toml_text::suggest;

std::string quote_key(std::string_view k_full) {
    // Key paths are for messages: a key of megabytes is shown by its start and its length.
    const std::string shown = toml_text::excerpt(k_full);
    const std::string_view k = k_full.size() > shown.size() ? std::string_view(shown) : k_full;
    const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
               c == '-';
    });
    return bare ? std::string(k) : toml_text::quoted(k);
}

std::string KeyPath::str() const {
    if (!parent) return {};
    std::string s = parent->str();
    if (index >= 0) return s + '[' + std::to_string(index) + ']';
    if (!s.empty()) s += '.';
    return s + quote_key(key);
}

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

std::string unknown_what(const toml::node& n) {
    return n.is_table() || n.is_array_of_tables() ? "unknown table" : "unknown key";
}

const toml::source_region& where(const toml::table& t, std::initializer_list<const toml::node*> nodes) {
    const toml::source_region* r = &t.source();
    for (const toml::node* n : nodes)
        if (n && (r == &t.source() || r->begin < n->source().begin)) r = &n->source();
    return *r;
}

const toml::node* last_of(std::initializer_list<const toml::node*> nodes) {
    const toml::node* last = nullptr;
    for (const toml::node* n : nodes)
        if (n && (!last || last->source().begin < n->source().begin)) last = n;
    return last;
}

namespace {

// Debian's toml++ 3.3.0 parses nested keys, tables and arrays by recursion, and about 31,000
// levels of `a.a.a...` or `[[[...` overflow the stack (SIGSEGV). No scene or preset nests more than a
// few levels, so nesting is bounded here, before the parser sees the text: dots in a key (outside
// quoted keys) and brackets or braces of values (outside strings and comments), named by line.
void check_nesting(std::string_view text, const std::string& file) {
    constexpr int kMaxDepth = 64;
    int line = 1, depth = 0, dots = 0;
    bool in_key = true;  // at the start of a line, until '=' (or a table header's closing ']')
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            dots = 0;
            in_key = depth == 0;
            continue;
        }
        if (c == '#') {  // a comment runs to the end of the line
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
            continue;
        }
        if (c == '"' || c == '\'') {  // a string: skipped whole, multi-line ones included
            const bool triple = text.substr(i, 3) == std::string(3, c);
            const std::string_view close = triple ? std::string_view(c == '"' ? "\"\"\"" : "'''") : std::string_view(&text[i], 1);
            std::size_t j = i + (triple ? 3 : 1);
            for (; j < text.size(); ++j) {
                if (text[j] == '\n') {
                    if (!triple) { --j; break; }  // unterminated: the parser names it; the newline is counted above
                    ++line;
                }
                if (c == '"' && text[j] == '\\') { ++j; continue; }
                if (text.substr(j, close.size()) == close) break;
            }
            i = j + (triple ? 2 : 0);
            continue;
        }
        if (in_key && c == '.' && ++dots > kMaxDepth)
            throw SceneFileError(file, line, 0, "", "a key nested deeper than " + std::to_string(kMaxDepth) + " levels");
        if (c == '=') in_key = false;
        if (!in_key && (c == '[' || c == '{') && ++depth > kMaxDepth)
            throw SceneFileError(file, line, 0, "", "a value nested deeper than " + std::to_string(kMaxDepth) + " levels");
        if (!in_key && (c == ']' || c == '}') && depth > 0) --depth;
    }
}

toml::table parse_document(std::string_view text, const std::string& file) {
    check_nesting(text, file);
    try {
        return toml::parse(text, std::string_view(file));
    } catch (const toml::parse_error& e) {
        throw SceneFileError(file, static_cast<int>(e.source().begin.line), static_cast<int>(e.source().begin.column),
                             "", "invalid TOML: " + std::string(e.description()));
    }
}

}  // namespace

Reader::Reader(std::string_view text, const std::string& file) : file_(file), root_(parse_document(text, file)) {}

void Reader::fail(const toml::source_region& where, const KeyPath& path, const std::string& problem) const {
    throw SceneFileError(file_, static_cast<int>(where.begin.line), 0, path.str(), problem);
}

void Reader::fail(const toml::node& n, const KeyPath& path, const std::string& problem) const {
    fail(n.source(), path, problem);
}

// toml++ iterates a table in key order, not file order: the first in the file is the one reported.
const toml::key* Reader::first_unknown(const toml::table& t, std::span<const std::string_view> known) {
    const toml::key* first = nullptr;
    for (auto&& [k, v] : t) {
        if (contains(known, k.str())) continue;
        if (!first || k.source().begin < first->source().begin) first = &k;
    }
    return first;
}

void Reader::check_root_keys(std::span<const std::string_view> known,
                             std::initializer_list<std::span<const SectionHint>> homes,
                             std::span<const std::string_view> refused, std::string_view refused_problem) const {
    homes_.clear();
    for (const std::span<const SectionHint> sections : homes) homes_.insert(homes_.end(), sections.begin(), sections.end());
    const toml::key* first = first_unknown(root_, known);
    if (!first) return;
    const std::string_view name = first->str();
    std::string problem = unknown_what(root_.at(name));
    const auto home = std::ranges::find_if(homes_, [&](const SectionHint& s) { return contains(s.keys, name); });
    if (contains(refused, name))
        problem = std::string(refused_problem);
    else if (const auto s = suggest(name, known))
        problem += " (did you mean \"" + std::string(*s) + "\"?)";
    else if (home != homes_.end())
        problem += " (" + std::string(home->hint) + ")";
    else
        problem += " (allowed at the top level: " + join(known) + ")";
    const KeyPath top;
    fail(first->source(), top / name, problem);
}

const char* Reader::only_home_of(std::string_view key) const {
    const char* home = nullptr;
    for (const SectionHint& s : homes_) {
        if (!contains(s.keys, key)) continue;
        if (home) return nullptr;
        home = s.hint;
    }
    return home;
}

const toml::table& Reader::table(const toml::node& n, const KeyPath& path) const {
    const toml::table* t = n.as_table();
    if (!t) fail(n, path, "must be a table (got " + describe(n) + ")");
    return *t;
}

const toml::array& Reader::table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
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

const toml::array& Reader::inline_table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                              const char* what, const char* example) const {
    const toml::array* a = n.as_array();
    if (!a) fail(n, path, "must be an array of tables such as " + std::string(example) + " (got " + describe(n) + ")");
    return elements_are_tables(*a, path, limit, what);
}

const toml::array& Reader::elements_are_tables(const toml::array& a, const KeyPath& path, std::size_t limit,
                                               const char* what) const {
    if (a.size() > limit)
        fail(a, path,
             "absurd size: too many " + std::string(what) + " (got " + std::to_string(a.size()) +
                 ", the limit is " + std::to_string(limit) + ")");
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!a[i].is_table()) fail(a[i], path[i], "must be a table (got " + describe(a[i]) + ")");
    return a;
}

const toml::node& Reader::required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                                   std::string_view needs) const {
    const toml::node* n = t.get(key);
    if (!n) fail(t.source(), table_path / key, "missing (" + std::string(needs) + ")");
    return *n;
}

const toml::node& Reader::required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                                   std::span<const std::string_view> all) const {
    const toml::node* n = t.get(key);
    if (!n)
        fail(t.source(), table_path / key,
             "missing (each [[" + std::string(table_path.parent->key) + "]] needs " + join(all) + ")");
    return *n;
}

double Reader::number(const toml::node& n, const KeyPath& path) const {
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

double Reader::at_most(const toml::node& n, const KeyPath& path, double v, double max) const {
    if (!(v <= max)) fail(n, path, "absurd size: must be at most " + limit_text(max) + " (got " + shortest(v) + ")");
    return v;
}

double Reader::non_negative(const toml::node& n, const KeyPath& path, double max) const {
    const double v = number(n, path);
    if (!(v >= 0.0)) fail(n, path, "must not be negative (got " + shortest(v) + ")");
    return at_most(n, path, v, max);
}

double Reader::positive(const toml::node& n, const KeyPath& path, double max) const {
    const double v = number(n, path);
    if (!(v > 0.0)) fail(n, path, "must be positive (got " + shortest(v) + ")");
    return at_most(n, path, v, max);
}

double Reader::bounded(const toml::node& n, const KeyPath& path, double max) const {
    const double v = number(n, path);
    if (!(std::abs(v) <= max))
        fail(n, path, "absurd size: must be within " + limit_text(max) + " of 0 (got " + shortest(v) + ")");
    return v;
}

double Reader::in_interval(const toml::node& n, const KeyPath& path, double lo, double hi, bool open_below,
                           const char* unit) const {
    const double v = number(n, path);
    if (!((open_below ? v > lo : v >= lo) && v <= hi))
        fail(n, path,
             std::string("must be in ") + (open_below ? "(" : "[") + limit_text(lo) + ", " + limit_text(hi) + "]" +
                 unit + " (got " + shortest(v) + ")");
    return v;
}

std::int64_t Reader::integer_in(const toml::node& n, const KeyPath& path, std::int64_t lo, std::int64_t hi) const {
    const auto* i = n.as_integer();
    if (!i) fail(n, path, "must be an integer (got " + describe(n) + ")");
    const std::int64_t v = i->get();
    if (v < lo || v > hi)
        fail(n, path,
             "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " + std::to_string(v) +
                 ")");
    return v;
}

std::string_view Reader::string(const toml::node& n, const KeyPath& path) const {
    const auto* s = n.as_string();
    if (!s) fail(n, path, "must be a string (got " + describe(n) + ")");
    return s->get();
}

bool Reader::boolean(const toml::node& n, const KeyPath& path) const {
    const auto* b = n.as_boolean();
    if (!b) fail(n, path, "must be true or false (got " + describe(n) + ")");
    return b->get();
}

std::string Reader::one_line(const toml::node& n, const KeyPath& path) const {
    const std::string_view s = string(n, path);
    if (std::any_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
        fail(n, path, "must be one line of text without control characters (got " + toml_text::quoted(toml_text::excerpt(s)) + ")");
    return std::string(s);
}

std::size_t Reader::choice(const toml::node& n, const KeyPath& path, std::span<const std::string_view> names) const {
    const std::string_view s = string(n, path);
    const auto it = std::find(names.begin(), names.end(), s);
    if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
    std::string problem = "must be one of";
    for (std::size_t i = 0; i < names.size(); ++i) problem += std::string(i ? ", " : " ") + toml_text::quoted(names[i]);
    problem += " (got " + toml_text::quoted(toml_text::excerpt(s));
    if (const auto close = suggest(s, names)) problem += "; did you mean " + toml_text::quoted(*close) + "?";
    fail(n, path, problem + ")");
}

Vec3Field Reader::vec3(const toml::node& n, const KeyPath& path) const {
    const toml::array* a = n.as_array();
    if (!a) fail(n, path, "must be an array of 3 numbers (got " + describe(n) + ")");
    if (a->size() != 3) fail(n, path, "must be an array of exactly 3 numbers (got " + std::to_string(a->size()) + ")");
    Vec3Field f;
    for (std::size_t c = 0; c < 3; ++c) {
        f.elems[c] = &(*a)[c];
        f.v[static_cast<int>(c)] = number(*f.elems[c], path[c]);
    }
    return f;
}

glm::dvec3 Reader::coordinates(const toml::node& n, const KeyPath& path) const {
    const Vec3Field f = vec3(n, path);
    each(f, path, [](double v) { return std::abs(v) <= kMaxCoordinate; },
         "absurd size: coordinates must be within 1e7 of the origin");
    return f.v;
}

glm::dvec3 Reader::direction(const toml::node& n, const KeyPath& path) const {
    const glm::dvec3 v = coordinates(n, path);
    if (!(glm::length(v) > 0.0)) fail(n, path, "must not be zero (it is normalised)");
    return v;
}

glm::dvec3 Reader::radiance(const toml::node& n, const KeyPath& path) const {
    const Vec3Field f = vec3(n, path);
    each(f, path, [](double v) { return v >= 0.0; }, "must not be negative");
    each(f, path, [](double v) { return v <= kMaxRadiance; }, "absurd size: must be at most 1e9");
    return f.v;
}

Vec3Field Reader::albedo(const toml::node& n, const KeyPath& path) const {
    const Vec3Field f = vec3(n, path);
    each(f, path, [](double v) { return v >= 0.0 && v <= 1.0; }, "must be in [0, 1]");
    return f;
}

}  // namespace brume::toml_read
