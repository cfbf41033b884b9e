#include "app/preview_edit.h"

#include "render/atomic_file.h"
#include "sim/preset_file.h"
#include "sim/scene_file.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace brume::app {

struct PresetEditor::Document {
    toml::table root;      // the current, edited values
    toml::table original;  // as read, with the source positions of every value
    toml::table shown;     // root as of the last keep_shown()
};

namespace {

struct Segment {
    std::string name;
    long long index = -1;  // name[index], or -1
};

std::vector<Segment> parse_key_path(const std::string& path) {
    std::vector<Segment> out;
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t dot = path.find('.', start);
        std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        Segment s;
        if (const std::size_t open = part.find('['); open != std::string::npos) {
            long long i = -1;
            const auto [end, ec] = std::from_chars(part.data() + open + 1, part.data() + part.size(), i);
            if (ec != std::errc() || i < 0 || end != part.data() + part.size() - 1 || part.back() != ']')
                throw std::invalid_argument("set " + path + ": '" + part + "' is not NAME or NAME[INDEX]");
            s.index = i;
            part.resize(open);
        }
        if (part.empty()) throw std::invalid_argument("set " + path + ": an empty key in the path");
        s.name = part;
        out.push_back(s);
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    return out;
}

// The node the path names inside `root`, creating plain tables on the way; the last segment is
// assigned `value`.
template <typename Value>
void assign(toml::table& root, const std::vector<Segment>& path, const std::string& text, Value&& value) {
    toml::table* table = &root;
    for (std::size_t k = 0; k < path.size(); ++k) {
        const Segment& s = path[k];
        const bool last = k + 1 == path.size();
        if (s.index < 0) {
            if (last) {
                table->insert_or_assign(s.name, std::move(value));
                return;
            }
            toml::node* next = table->get(s.name);
            if (!next) next = &table->insert_or_assign(s.name, toml::table{}).first->second;
            table = next->as_table();
            if (!table) throw std::invalid_argument("set " + text + ": " + s.name + " is not a table");
            continue;
        }
        toml::array* array = table->get_as<toml::array>(s.name);
        if (!array) throw std::invalid_argument("set " + text + ": " + s.name + " is not an array");
        if (std::size_t(s.index) >= array->size())
            throw std::invalid_argument("set " + text + ": " + s.name + " has " + std::to_string(array->size()) +
                                        " entries (0-based)");
        if (last) {
            array->replace(array->cbegin() + s.index, std::move(value));
            return;
        }
        table = array->get(std::size_t(s.index))->as_table();
        if (!table) throw std::invalid_argument("set " + text + ": " + s.name + "[" + std::to_string(s.index) +
                                                "] is not a table");
    }
}

void collect(const toml::node& node, const std::string& path, std::vector<EditableValue>& out) {
    EditableValue v;
    v.path = path;
    if (const toml::table* t = node.as_table()) {
        for (const auto& [key, child] : *t)
            collect(child, path.empty() ? std::string(key.str()) : path + "." + std::string(key.str()), out);
        return;
    }
    if (const toml::array* a = node.as_array()) {
        bool numeric = a->size() >= 2 && a->size() <= 4;
        for (const toml::node& e : *a) numeric = numeric && (e.is_floating_point() || e.is_integer());
        if (numeric) {
            v.kind = EditableValue::Kind::Numbers;
            v.integers = true;
            for (const toml::node& e : *a) v.integers = v.integers && e.is_integer();
            for (const toml::node& e : *a) v.numbers.push_back(e.value<double>().value_or(0.0));
            out.push_back(v);
            return;
        }
        for (std::size_t i = 0; i < a->size(); ++i) collect(*a->get(i), path + "[" + std::to_string(i) + "]", out);
        return;
    }
    if (node.is_floating_point()) {
        v.kind = EditableValue::Kind::Number;
        v.numbers = {*node.value<double>()};
    } else if (node.is_integer()) {
        v.kind = EditableValue::Kind::Integer;
        v.numbers = {double(*node.value<std::int64_t>())};
    } else if (node.is_boolean()) {
        v.kind = EditableValue::Kind::Bool;
        v.flag = *node.value<bool>();
    } else if (node.is_string()) {
        v.kind = EditableValue::Kind::String;
        v.text = *node.value<std::string>();
    } else {
        return;  // dates and times: no preset key uses them
    }
    out.push_back(v);
}

std::string float_text(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    std::string s = buf;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "n": nan and inf stay as they are
    return s;
}

}  // namespace

std::string toml_value_text(const EditableValue& v) {
    switch (v.kind) {
    case EditableValue::Kind::Number: return float_text(v.numbers.at(0));
    case EditableValue::Kind::Integer: return std::to_string(std::llround(v.numbers.at(0)));
    case EditableValue::Kind::Bool: return v.flag ? "true" : "false";
    case EditableValue::Kind::String: {
        std::string out = "\"";
        for (char c : v.text) {
            if (c == '"' || c == '\\') out += '\\';
            out += c;
        }
        return out + "\"";
    }
    case EditableValue::Kind::Numbers: {
        std::string out = "[";
        for (std::size_t i = 0; i < v.numbers.size(); ++i)
            out += (i ? ", " : "") + (v.integers ? std::to_string(std::llround(v.numbers[i])) : float_text(v.numbers[i]));
        return out + "]";
    }
    }
    return {};
}

std::vector<EditableValue> PresetEditor::values() const {
    std::vector<EditableValue> out;
    collect(doc_->root, "", out);
    return out;
}

PresetEditor::PresetEditor(const std::string& text, std::string source_name)
    : doc_(std::make_unique<Document>()), source_name_(std::move(source_name)), original_text_(text) {
    doc_->original = toml::parse(text, std::string_view(source_name_));
    doc_->root = doc_->original;
    doc_->shown = doc_->original;
}

void PresetEditor::keep_shown() {
    doc_->shown = doc_->root;
    shown_edits_ = edits_;
}

void PresetEditor::return_to_shown() {
    doc_->root = doc_->shown;
    edits_ = shown_edits_;
}

void PresetEditor::save(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && std::filesystem::equivalent(path, source_name_, ec)) {
        const std::string on_disk = toml_text::read_file(path);
        if (on_disk != original_text_ && on_disk != last_saved_text_)
            throw std::invalid_argument("save: " + path.string() +
                                        " changed on disk since the preview read it (a reload it refused, above?): "
                                        "saving would put the old text back over that change. Fix the file so that it "
                                        "reloads, or save the edits to another file");
    }
    const std::string text = saved_text();
    write_file_atomically(path, text);
    if (std::filesystem::equivalent(path, source_name_, ec)) last_saved_text_ = text;
}

PresetEditor::~PresetEditor() = default;

bool edit_affects_simulation(const std::string& key_path) {
    // The table the key is in: "lighting" of "lighting.sun[1]", "sphere" of "sphere[3].radius".
    const std::string table = key_path.substr(0, key_path.find_first_of(".["));
    static const char* const unread[] = {"lighting", "camera", "camera_path", "render", "render_settings",
                                         "preset",   "sphere", "vdb"};
    for (const char* t : unread)
        if (table == t) return false;
    return key_path != "timeline.duration";  // anything else, a key this list does not know included
}

std::optional<std::size_t> edited_emitter(const std::string& key_path) {
    const std::string prefix = "emitter[";
    if (key_path.rfind(prefix, 0) != 0) return std::nullopt;
    const std::size_t close = key_path.find(']', prefix.size());
    if (close == std::string::npos || close == prefix.size() || close - prefix.size() > 5) return std::nullopt;
    std::size_t index = 0;
    for (std::size_t i = prefix.size(); i < close; ++i) {
        if (key_path[i] < '0' || key_path[i] > '9') return std::nullopt;
        index = index * 10 + std::size_t(key_path[i] - '0');
    }
    return index;
}

Preset PresetEditor::set(const std::string& key_path, const std::string& value) {
    toml::table holder;
    try {
        holder = toml::parse("value = " + value);
    } catch (const toml::parse_error& e) {
        throw std::invalid_argument("set " + key_path + ": '" + value + "' is not a TOML value (" +
                                    std::string(e.description()) + ")");
    }
    toml::node* node = holder.get("value");
    if (!node) throw std::invalid_argument("set " + key_path + ": no value");
    toml::table edited = doc_->root;
    node->visit([&](auto& v) { assign(edited, parse_key_path(key_path), key_path, std::move(v)); });
    std::ostringstream text;
    text << edited;
    try {
        Preset preset = parse_preset_toml(text.str(), source_name_);
        // Its tables' lines are the regenerated text's, not the file's: the messages of its preparation
        // (a [[vdb]] volume's, a density emitter's) name the file and the table alone.
        for (VdbVolume& v : preset.scene.volumes) v.defined_at = source_name_;
        for (EmitterDesc& e : preset.emitters) e.defined_at = source_name_;
        doc_->root = std::move(edited);
        record_edit(key_path, value);
        return preset;
    } catch (const SceneFileError& e) {
        // The line would be the regenerated text's, not the file's: the key and the problem say it.
        throw std::invalid_argument((e.key_path().empty() ? "set " + key_path : e.key_path()) + ": " + e.problem());
    }
}

}  // namespace brume::app

namespace brume::app {
namespace {

bool is_inside(const std::string& path, const std::string& outer) {
    return path.size() > outer.size() && path.compare(0, outer.size(), outer) == 0 &&
           (path[outer.size()] == '.' || path[outer.size()] == '[');
}

// The node at `path` in `root`, or null; nothing is created.
const toml::node* find(const toml::table& root, const std::vector<Segment>& path) {
    const toml::node* node = &root;
    for (const Segment& s : path) {
        const toml::table* t = node->as_table();
        node = t ? t->get(s.name) : nullptr;
        if (!node) return nullptr;
        if (s.index >= 0) {
            const toml::array* a = node->as_array();
            node = a ? a->get(std::size_t(s.index)) : nullptr;
            if (!node) return nullptr;
        }
    }
    return node;
}

// Where a key that the original text lacks is written: after the last line holding a value of its
// table (before the table's sub-tables and the next header), or, when the table itself is missing
// and its parent exists, as a new "[table]" header after the parent's values (an [[array]] entry's
// sub-table header applies to the entry before it, so this works for emitter[2].curves too), or at
// the end for a missing top-level table.
struct Insertion {
    bool possible = false;
    std::size_t after_line = 0;  // 1-based; 0: at the end of the text
    std::string header;          // "[table]\n" when the table is new
    std::string why;             // when not possible
};

// The last line of `table`'s own values (not of its header sub-tables), or its header's line.
std::size_t last_value_line(const toml::table& table) {
    std::size_t line = table.source().begin.line;
    for (const auto& [key, child] : table) {
        if (const toml::table* t = child.as_table(); t && !t->is_inline()) continue;
        if (const toml::array* a = child.as_array(); a && a->is_array_of_tables() && !a->empty() &&
                                                     !a->get(0)->as_table()->is_inline())
            continue;
        line = std::max<std::size_t>(line, child.source().end.line);
    }
    return line;
}

Insertion insertion_for(const toml::table& root, const std::vector<Segment>& path) {
    Insertion out;
    if (path.back().index >= 0) {
        out.why = "an array entry cannot be added";
        return out;
    }
    const std::vector<Segment> parent_path(path.begin(), path.end() - 1);
    if (parent_path.empty()) {
        out.why = "a key outside every table cannot be placed";
        return out;
    }
    if (const toml::node* parent = find(root, parent_path)) {
        const toml::table* table = parent->as_table();
        if (!table || table->is_inline() || table->source().begin.line == 0) {
            out.why = "its table is not a [table] of the file";
            return out;
        }
        out.possible = true;
        out.after_line = last_value_line(*table);
        return out;
    }
    // The table is missing: its parent must exist (or be the root), and the table be a plain name.
    const Segment& missing = parent_path.back();
    if (missing.index >= 0) {
        out.why = "its table " + missing.name + " is an array entry the file lacks";
        return out;
    }
    std::string header;  // the header path: array indices drop out ("emitter.curves")
    for (const Segment& s : parent_path) header += (header.empty() ? "" : ".") + s.name;
    out.header = "\n[" + header + "]\n";
    const std::vector<Segment> grand_path(parent_path.begin(), parent_path.end() - 1);
    if (grand_path.empty()) {
        out.possible = true;  // a new top-level table at the end
        return out;
    }
    const toml::node* grand = find(root, grand_path);
    const toml::table* table = grand ? grand->as_table() : nullptr;
    if (!table || table->is_inline() || table->source().begin.line == 0) {
        out.why = "neither its table nor the one around it is in the file";
        return out;
    }
    out.possible = true;
    out.after_line = last_value_line(*table);
    return out;
}

}  // namespace

void PresetEditor::record_edit(const std::string& key_path, const std::string& value) {
    // A path inside one already edited (sun[1] after sun) changes that edit's text; a path around
    // earlier ones (sun after sun[1]) replaces them.
    for (auto& [path, text] : edits_) {
        if (is_inside(key_path, path)) {
            const std::vector<EditableValue> now = values();
            for (const EditableValue& v : now)
                if (v.path == path) text = toml_value_text(v);
            return;
        }
    }
    std::erase_if(edits_, [&](const auto& e) { return e.first == key_path || is_inside(e.first, key_path); });
    edits_.emplace_back(key_path, value);
}

std::string PresetEditor::saved_text() const {
    // Offsets of the original text's lines (toml++ positions are 1-based line and column).
    std::vector<std::size_t> line_start{0, 0};
    for (std::size_t i = 0; i < original_text_.size(); ++i)
        if (original_text_[i] == '\n') line_start.push_back(i + 1);
    struct Replacement {
        std::size_t begin, end;
        std::string text;
        int rank = 0;        // at one offset, new lines first (in edit order), then new tables
        std::string header;  // a new table's header: a second key of it joins the same block
    };
    std::vector<Replacement> replacements;
    // After line `line` (1-based): the offset where the next line starts (the end for the last line).
    const auto after_line = [&](std::size_t line) {
        return line + 1 < line_start.size() ? line_start[line + 1] : original_text_.size();
    };
    for (const auto& [path, text] : edits_) {
        const std::vector<Segment> segments = parse_key_path(path);
        const toml::node* node = find(doc_->original, segments);
        if (node && node->source().begin.line != 0) {
            const toml::source_region& r = node->source();
            replacements.push_back({line_start.at(r.begin.line) + r.begin.column - 1,
                                    line_start.at(r.end.line) + r.end.column - 1, text});
            continue;
        }
        // A key the file leaves out (its default): a new line in the table it belongs to.
        const Insertion at = insertion_for(doc_->original, segments);
        if (!at.possible)
            throw std::invalid_argument("save: " + path + " is not in " + source_name_ + " and " + at.why +
                                        "; add the key to the file");
        const std::size_t offset = at.after_line == 0 ? original_text_.size() : after_line(at.after_line);
        const std::string line = segments.back().name + " = " + text + "\n";
        const int rank = int(replacements.size()) + (at.header.empty() ? 0 : 1 << 20);
        bool joined = false;
        for (Replacement& r : replacements)
            if (!at.header.empty() && r.header == at.header && r.begin == offset) {
                r.text += line;
                joined = true;
            }
        if (!joined) replacements.push_back({offset, offset, at.header + line, rank, at.header});
    }
    // A file without a final newline: what is added at the end starts on a line of its own.
    for (Replacement& r : replacements)
        if (r.begin == r.end && r.begin == original_text_.size() && !original_text_.empty() && original_text_.back() != '\n' &&
            r.header.empty())
            r.text = "\n" + r.text;
    // From the end backwards, so earlier offsets stay valid; at one offset the last in order goes in first.
    std::sort(replacements.begin(), replacements.end(),
              [](const auto& a, const auto& b) { return a.begin != b.begin ? a.begin > b.begin : a.rank > b.rank; });
    std::string out = original_text_;
    for (const Replacement& r : replacements) out.replace(r.begin, r.end - r.begin, r.text);

    // What is written must read back as the preset the preview shows.
    std::ostringstream current;
    current << doc_->root;
    const std::string want = preset_to_toml(parse_preset_toml(current.str(), source_name_));
    std::string got;
    try {
        got = preset_to_toml(parse_preset_toml(out, source_name_));
    } catch (const SceneFileError& e) {
        throw std::invalid_argument(std::string("save: the edited file would not read: ") + e.what());
    }
    if (got != want) throw std::invalid_argument("save: the edited file would not read back as the preview shows it");
    return out;
}

}  // namespace brume::app
