// The toolkit the scene and preset readers share (sim/scene_sections.h, sim/preset_sections.h): key
// paths that are formatted only when an error needs them, typed readers of numbers, vectors and tables
// that reject a bad value as a SceneFileError "file:line: key: problem", and the unknown-key checks with
// their "did you mean" suggestions. It knows no section, so both readers build on it without depending on
// each other. Internal to brume_sim: it exposes toml++, which nothing outside sim/ includes.
#pragma once

#include "sim/scene_file.h"

#include <glm/vec3.hpp>
#include <toml++/toml.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace brume::toml_read {

// A key as messages print it: bare when TOML would allow it bare, else quoted.
std::string quote_key(std::string_view k);

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

    std::string str() const;  // "emitter[0].speed"
};

// "a, b, c".
std::string join(std::span<const std::string_view> names);
bool contains(std::span<const std::string_view> names, std::string_view name);
// "1e7" rather than to_chars' "1e+07" in messages about limits.
std::string limit_text(double v);
// What a node holds, for "(got ...)": "a string \"x\"", "an array of 2 element(s)", "a table".
std::string describe(const toml::node& n);
// "[camra]" is reported as a table, "raduis = 1" as a key.
std::string unknown_what(const toml::node& n);

// A 3-vector with its elements' nodes, so that an error about one component points at it.
struct Vec3Field {
    glm::dvec3 v{0.0};
    std::array<const toml::node*, 3> elems{};
};

// Where a key misplaced at the top level belongs ("width" above [camera]).
struct SectionHint {
    std::span<const std::string_view> keys;  // the keys the section reads
    const char* hint;                        // "it belongs under [camera]"
};

// The line of the last present key among candidates, else the table's: where a cross-key error points.
const toml::source_region& where(const toml::table& t, std::initializer_list<const toml::node*> nodes);
// The present node that comes last in the file (nullptr if none): where a cross-key error points.
const toml::node* last_of(std::initializer_list<const toml::node*> nodes);

// One document and the readers of its values: every error names `file` (which must outlive the reader).
class Reader {
public:
    // Parses `text`; invalid TOML is a SceneFileError with the line and column.
    Reader(std::string_view text, const std::string& file);

    const toml::table& root() const { return root_; }
    // "FILE:LINE" of `n`, for a message raised after reading (a [[vdb]] volume's conversion).
    std::string location(const toml::node& n) const { return file_ + ":" + std::to_string(n.source().begin.line); }

    [[noreturn]] void fail(const toml::source_region& where, const KeyPath& path, const std::string& problem) const;
    [[noreturn]] void fail(const toml::node& n, const KeyPath& path, const std::string& problem) const;

    // The first key in the file that is not in `allowed`. A key in `elsewhere` (used by another shape or
    // type) is explained by `misplaced`. Any other is pointed to the one section that reads it, with the
    // list of `allowed` ("fps" under [camera]: "it belongs under [timeline]", not a guess of "up"; the
    // sections are those check_root_keys was given), else gets a suggestion from `allowed` when one is
    // close, else the list.
    template <class Misplaced>
    void check_keys(const toml::table& t, const KeyPath& table_path, std::span<const std::string_view> allowed,
                    std::span<const std::string_view> elsewhere, Misplaced misplaced) const {
        const toml::key* first = first_unknown(t, allowed);
        if (!first) return;
        const std::string_view name = first->str();
        std::string problem;
        if (contains(elsewhere, name))
            problem = misplaced(name);
        else if (const char* home = only_home_of(name))
            problem = unknown_what(t.at(name)) + " (" + home + "; allowed here: " + join(allowed) + ")";
        else if (const auto s = toml_text::suggest(name, allowed))
            problem = unknown_what(t.at(name)) + " (did you mean \"" + std::string(*s) + "\"?)";
        else
            problem = unknown_what(t.at(name)) + " (allowed here: " + join(allowed) + ")";
        fail(first->source(), table_path / name, problem);
    }
    void check_keys(const toml::table& t, const KeyPath& table_path, std::span<const std::string_view> known) const {
        check_keys(t, table_path, known, {}, [](std::string_view) { return std::string(); });
    }

    // The first top-level key not in `known`. One in `refused` (a section another kind of document
    // holds) is answered with `refused_problem`; any other gets a suggestion from `known` when one is
    // close, else the section of `homes` it belongs in (the first that reads it), else the list of `known`.
    // The document's sections are read after this check: `homes` is kept for their checks (check_keys).
    void check_root_keys(std::span<const std::string_view> known,
                         std::initializer_list<std::span<const SectionHint>> homes,
                         std::span<const std::string_view> refused = {},
                         std::string_view refused_problem = {}) const;

    const toml::table& table(const toml::node& n, const KeyPath& path) const;
    // A section's table, its keys checked against `known`.
    const toml::table& table(const toml::node& n, const KeyPath& path, std::span<const std::string_view> known) const {
        const toml::table& t = table(n, path);
        check_keys(t, path, known);
        return t;
    }
    // A top-level array of tables ([[box]]), its length checked against a limit, each element a table.
    const toml::array& table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                   const char* what) const;
    // An array of inline tables inside a section (bursts = [{ time = 0.5, count = 200 }]).
    const toml::array& inline_table_array(const toml::node& n, const KeyPath& path, std::size_t limit,
                                          const char* what, const char* example) const;

    // Appends read(reader, table, path) for each table of `a` (checked by table_array or
    // inline_table_array) to `out`, in file order: while one is read, `out` holds those before it.
    template <class T, class Read>
    void read_each(const toml::array& a, const KeyPath& path, std::vector<T>& out, Read read) const {
        out.reserve(out.size() + a.size());
        for (std::size_t i = 0; i < a.size(); ++i) out.push_back(read(*this, *a[i].as_table(), path[i]));
    }
    // The same for a top-level array of tables ([[box]]), checked by table_array first.
    template <class T, class Read>
    void read_each(const toml::node& n, const KeyPath& path, std::size_t limit, const char* what,
                   std::vector<T>& out, Read read) const {
        read_each(table_array(n, path, limit, what), path, out, read);
    }

    // A key the section cannot do without; the error points at the section's header.
    const toml::node& required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                               std::string_view needs) const;
    // In a top-level [[section]], every key of which is required.
    const toml::node& required(const toml::table& t, std::string_view key, const KeyPath& table_path,
                               std::span<const std::string_view> all) const;

    // --- Scalars ---------------------------------------------------------------------------------

    // Integers are accepted where floats are expected; NaN and Inf never are.
    double number(const toml::node& n, const KeyPath& path) const;
    double at_most(const toml::node& n, const KeyPath& path, double v, double max) const;
    double non_negative(const toml::node& n, const KeyPath& path, double max) const;
    double positive(const toml::node& n, const KeyPath& path, double max) const;
    // |v| <= max: a signed quantity of bounded size.
    double bounded(const toml::node& n, const KeyPath& path, double max) const;
    // lo <= v <= hi, or lo < v <= hi when open_below; `unit` follows the interval in the message.
    double in_interval(const toml::node& n, const KeyPath& path, double lo, double hi, bool open_below,
                       const char* unit = "") const;
    std::int64_t integer_in(const toml::node& n, const KeyPath& path, std::int64_t lo, std::int64_t hi) const;
    std::string_view string(const toml::node& n, const KeyPath& path) const;
    // true or false only: "yes", 1 and the like are refused, so a typo cannot flip a switch silently.
    bool boolean(const toml::node& n, const KeyPath& path) const;
    // Names and descriptions are printed on one line (`brume play --list`, messages).
    std::string one_line(const toml::node& n, const KeyPath& path) const;
    // One of `names`; returns its index (the enum value).
    std::size_t choice(const toml::node& n, const KeyPath& path, std::span<const std::string_view> names) const;

    // --- Vectors ---------------------------------------------------------------------------------

    Vec3Field vec3(const toml::node& n, const KeyPath& path) const;
    // Every component satisfies ok, else the error points at the first that does not, citing `rule`.
    template <class Ok>
    void each(const Vec3Field& f, const KeyPath& path, Ok ok, const char* rule) const {
        for (std::size_t c = 0; c < 3; ++c) {
            const double v = f.v[static_cast<int>(c)];
            if (!ok(v)) fail(*f.elems[c], path[c], std::string(rule) + " (got " + toml_text::shortest(v) + ")");
        }
    }
    // A position or direction: bounded so that squaring it (lengths, intersections) stays finite.
    glm::dvec3 coordinates(const toml::node& n, const KeyPath& path) const;
    // A direction that is normalised where it is used.
    glm::dvec3 direction(const toml::node& n, const KeyPath& path) const;
    glm::dvec3 radiance(const toml::node& n, const KeyPath& path) const;
    Vec3Field albedo(const toml::node& n, const KeyPath& path) const;

private:
    static const toml::key* first_unknown(const toml::table& t, std::span<const std::string_view> known);
    const toml::array& elements_are_tables(const toml::array& a, const KeyPath& path, std::size_t limit,
                                           const char* what) const;
    // The hint of the one section that reads `key`; nullptr when none or several do ("radius").
    const char* only_home_of(std::string_view key) const;

    const std::string& file_;
    toml::table root_;
    // The document's sections, as check_root_keys last saw them. Mutable because the document is read
    // through a const Reader; the check runs before any section is read.
    mutable std::vector<SectionHint> homes_;
};

}  // namespace brume::toml_read
