// The preview's ImGui panel: timeline (play, pause, loop, speed, step, scrub, the simulated and
// checkpointed range), camera (follow the path, reset, exposure), the preset's values (live edits),
// method (every GPU method of the
// registry with its setting) and the live figures of the frame (FPS, CPU time per part, GPU ms per
// pass, fragments, pool memory, list lengths, internal resolution). It only edits the session and
// the flags below; the loop applies them.
#pragma once

#include "app/preview_adaptive.h"
#include "app/preview_edit_panel.h"
#include "app/preview_reference.h"
#include "app/preview_session.h"

#include <functional>
#include <string>

namespace brume::app {

// Wall-clock milliseconds of each part of the last frame, smoothed.
struct PartTimes {
    double simulate = 0.0, render = 0.0, ui = 0.0, present = 0.0, frame = 0.0;
};

struct PanelState {
    PreviewSession& session;
    AdaptiveResolution& adaptive;
    const PartTimes& times;
    VkExtent2D viewport{};
    VkExtent2D internal{};
    bool list_stats = false;     // ask the method for list lengths (extra atomics)
    std::string method_error;    // the last refused method switch, shown until the next one
    std::string reload_error;    // the watched file's error while it does not read; the last good preset plays
    std::string watched_file;    // empty: nothing is watched (a built-in preset)
    char method_setting[32] = {};  // the setting text being edited
    int method_index = 0;          // into the GPU methods of the catalogue
    int compare_index = 0;         // the second method, for the split and difference views
    int compare_mode = 0;          // 0 off, 1 split, 2 difference
    PresetEditPanel preset_edit;   // the "Preset" section's values and edits
    ReferenceCheck* reference = nullptr;       // the error against the reference, on a worker thread
    std::function<void()> start_reference;     // starts a check of the frame shown
};

// Draws the panel for this UI frame.
void draw_panel(PanelState& state);

}  // namespace brume::app
