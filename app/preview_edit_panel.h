// The panel's "Preset" section: every value of the preset's TOML (app/preview_edit.h), grouped by
// section, each with a widget of its kind. A changed value is handed to `set`, which edits the
// preset and applies it at the same frame, so the view updates at once (or, for a preset with
// density grids, once a worker has prepared it); a refused value shows the reader's message. "Save" writes the edits into the file where the values stand.
#pragma once

#include "app/preview_edit.h"

#include <functional>
#include <string>
#include <vector>

namespace brume::app {

struct PresetEditPanel {
    std::vector<EditableValue> values;  // refreshed from the editor after every accepted edit
    bool stale = true;
    std::string error;  // the last refused edit
    // Applies KEY.PATH = VALUE; returns the refusal, empty when it was accepted.
    std::function<std::string(const std::string& path, const std::string& value)> set;
    std::function<std::vector<EditableValue>()> read;
    // Writes the edited preset to `save_path` (comments and layout kept); returns the refusal or "".
    std::function<std::string()> save;
    std::string save_path;
    std::string saved;  // what the last save wrote, for the panel
    std::function<bool()> preparing;  // an accepted edit is still being prepared on a worker
};

// Draws the section's contents (inside the panel window).
void draw_preset_editor(PresetEditPanel& panel);

}  // namespace brume::app
