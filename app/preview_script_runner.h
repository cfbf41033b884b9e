// The executor of `brume preview --script` (the commands parsed by app/preview_script.h): runs them
// against the preview's session, renderer, window and workers, one shown frame at a time, and waits
// where a command has to (a frame count, a reload, a screenshot job, a reference check, a prepared edit,
// a sequence render, a capture of the next frame shown).
#pragma once

#include "app/preview_script.h"
#include "sim/preset.h"

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace brume {
class SwapchainPresenter;
}

namespace brume::app {

class PreviewSession;
class PreviewRenderer;
class PreviewWindow;
class PresetWatcher;
class PresetEditor;
class ReferenceCheck;
class SequenceRender;
class PendingEdit;

// What a script command reaches besides the session.
struct ScriptTargets {
    PreviewSession& session;
    PreviewRenderer& renderer;  // screenshots are rendered there (a job: never dropped)
    const PreviewWindow& window;
    SwapchainPresenter& presenter;
    bool& panel_visible;
    const PresetWatcher* watcher;  // null: a built-in preset, nothing to reload
    std::unique_ptr<PresetEditor>& editor;
    // The preset as `brume play` would prepare it: the viewport's size, the grid files beside the file.
    std::function<void(Preset&)> prepare;
    bool& preset_edit_stale;  // the panel's list of values, read again after a scripted edit
    ReferenceCheck& reference;
    std::function<void()> start_reference;
    std::function<bool()> reference_busy;  // its frame is rendering, or the reference is
    SequenceRender& sequence;
    // Starts brume play of frames first-last into dir with the preview's options; throws when refused.
    std::function<void(const std::string& dir, int first, int last, const std::string& formats)> start_sequence;
    // Applies an edited preset (read, not prepared): at once, or on a worker when preparing it is
    // slow (app/preview_pending_edit.h); true when it went to the worker.
    std::function<bool(Preset edited, const std::string& key)> submit_edit;
    PendingEdit& pending_edit;
    std::string& pending_edit_error;
};

// Runs script commands until one has to wait for shown frames, or the script ends. Returns false
// once `quit` ran.
class ScriptRunner {
public:
    explicit ScriptRunner(std::vector<ScriptCommand> commands) : commands_(commands.begin(), commands.end()) {}

    bool active() const {
        return !commands_.empty() || reload_wait_.active || reference_wait_ || sequence_wait_ || edit_wait_ ||
               screenshot_.id != 0;
    }
    // Waiting on something other than shown frames (a reload, a worker's edit, the reference, a sequence,
    // a screenshot job): the view need not be rendered again meanwhile, as a step of `wait N` needs.
    bool blocked() const {
        return reload_wait_.active || reference_wait_ || sequence_wait_ || edit_wait_ || screenshot_.id != 0;
    }
    // A capture waits for the next frame shown: the main loop asks the presenter to copy it.
    bool wants_capture() const { return !capture_.path.empty(); }
    // After each shown frame: counts down a wait, and writes a capture asked for by the last command.
    void frame_shown(SwapchainPresenter& presenter);
    // Executes what can run now. Throws std::runtime_error prefixed with "FILE:LINE: ".
    bool run(ScriptTargets& targets);

private:
    bool execute(const ScriptCommand& c, ScriptTargets& targets);

    using Clock = std::chrono::steady_clock;
    std::deque<ScriptCommand> commands_;
    bool sequence_wait_ = false;
    std::string sequence_where_;
    bool edit_wait_ = false;
    std::string edit_where_;
    bool reference_wait_ = false;
    std::string reference_where_;
    struct ReloadWait {
        bool active = false;
        int seen = 0;
        Clock::time_point since;
        std::string where;
    } reload_wait_;
    struct PendingCapture {
        std::string path, where;
    } capture_;
    struct PendingScreenshot {
        std::uint64_t id = 0;  // the render thread's job; 0: none
        std::string path, where, line;
        bool heat_map = false;
    } screenshot_;
    // The script starts once the first frame is on the screen, so every run shows the window working.
    long long frames_to_wait_ = 1;
};

}  // namespace brume::app
