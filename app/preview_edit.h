// Live edits of the preset (`set KEY.PATH VALUE` in a script): the preset's TOML is edited in memory
// and read again by the preset reader, so every value is validated exactly as in a file. KEY.PATH is
// the key path the reader's errors use: `emitter[0].rate`, `lighting.sun`, `timeline.duration`,
// `lighting.sun[1]`; VALUE is TOML (`2.5`, `[1.0, 0.9, 0.8]`, `"name"`). Edits accumulate; a hot
// reload starts again from the file. Saving writes the edited values into the original text in place.
#pragma once

#include "sim/preset.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace brume::app {

// Whether an edit of KEY.PATH changes what the simulator computes: emitters, forces, boxes (its
// obstacles) and the timeline's clock, seed and budget do; lighting, the camera and its path, the
// render settings, fixed spheres and volumes, the name and the duration do not (the simulator reads
// none of them: sim/simulator.h), so the frames simulated before such an edit stay valid.
bool edit_affects_simulation(const std::string& key_path);
// The emitter an edit changes alone ("emitter[2].rate", "emitter[0].curves.fade_in": 2, 0), for
// PreviewTimeline::replace_emitter_keeping_past; nullopt for any other key, and for "", which stands
// for several edits merged (preview_pending_edit.cpp).
std::optional<std::size_t> edited_emitter(const std::string& key_path);

// One value of the preset's TOML that the panel can edit: a number, an integer, a boolean, a string,
// or a short array of numbers (a vector, a range).
struct EditableValue {
    enum class Kind { Number, Integer, Bool, String, Numbers };
    std::string path;  // as set() takes it
    Kind kind = Kind::Number;
    std::vector<double> numbers;  // Number, Integer (one), Numbers (2 to 4)
    bool integers = false;        // Numbers: every element was written as an integer
    bool flag = false;
    std::string text;
};

// VALUE text for set(): floats always with a point or an exponent, so they stay floats in TOML.
std::string toml_value_text(const EditableValue& value);

class PresetEditor {
public:
    // `text`: the preset's TOML as read; `source_name`: the file (or built-in name) for messages.
    PresetEditor(const std::string& text, std::string source_name);
    ~PresetEditor();

    // Sets KEY.PATH to VALUE and returns the preset read back (not yet prepared). On any error the
    // edit is not kept, and std::invalid_argument names the key and the problem.
    Preset set(const std::string& key_path, const std::string& value);
    // Every editable value of the current text, by key path (sections sorted by name).
    std::vector<EditableValue> values() const;
    // The original text with each edited value replaced where it stands, so comments, order and
    // layout stay; checked to read back as the edited preset. Throws std::invalid_argument when an
    // edited key is not in the original text (it cannot be written in place) or the check fails.
    std::string saved_text() const;
    bool edited() const { return !edits_.empty(); }

    // The preview shows the preset of the edits up to the last keep_shown(). An edit whose preparation
    // then fails (a [[vdb]] tolerance the grid cannot meet, found on the worker) is dropped again by
    // return_to_shown(), with any made after it: Save never writes an edit the preview refused.
    void keep_shown();
    void return_to_shown();

    // Save into `path`, refused (std::invalid_argument) where `path` is the file this editor was read from
    // and that file no longer holds the text read (or last saved): an edit on disk whose reload was
    // refused would otherwise be overwritten by the old text plus the preview's edits.
    void save(const std::filesystem::path& path);

private:
    void record_edit(const std::string& key_path, const std::string& value);

    struct Document;
    std::unique_ptr<Document> doc_;
    std::string source_name_;
    std::string original_text_;
    std::string last_saved_text_;  // what save() last wrote to the source file
    std::vector<std::pair<std::string, std::string>> edits_;  // key path, value text; no path inside another
    std::vector<std::pair<std::string, std::string>> shown_edits_;
};

}  // namespace brume::app
