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
#include "app/preview_sequence.h"
#include "app/preview_session.h"

#include <functional>
#include <string>

namespace brume::app {

// Wall-clock milliseconds of each part of the last frame, smoothed. upload: building the frame's
// scene (the particles as spheres) and copying it to the device; render: the GPU passes, waited for.
struct PartTimes {
    double simulate = 0.0, upload = 0.0, render = 0.0, ui = 0.0, present = 0.0, frame = 0.0;
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
    std::string view_error;      // why the frame asked for was not rendered (RenderedFrame::refused); the last one stays
    std::string watched_file;    // empty: nothing is watched (a built-in preset)
    char method_setting[32] = {};  // the setting text being edited
    int method_index = 0;          // into the GPU methods of the catalogue
    int compare_index = 0;         // the second method, for the split and difference views
    int compare_mode = 0;          // 0 off, 1 split, 2 difference
    PresetEditPanel preset_edit;   // the "Preset" section's values and edits
    ReferenceCheck* reference = nullptr;       // the error against the reference, on a worker thread
    std::function<void()> start_reference;     // starts a check of the frame shown
    // Render sequence: brume play in the background; start_sequence returns an error, or empty.
    SequenceRender* sequence = nullptr;
    std::function<std::string(const std::string& dir, int first, int last, const std::string& formats)> start_sequence;
    char sequence_dir[256] = "";
    int sequence_first = 0, sequence_last = -1;  // -1: the last frame
    bool sequence_png = true, sequence_exr = false;
    std::string sequence_error;
};

// Draws the panel for this UI frame.
void draw_panel(PanelState& state);

}  // namespace brume::app
