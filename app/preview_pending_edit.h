// An edit of a preset that holds density grids is prepared on a worker thread: preparing converts
// every [[vdb]] grid to spheres and reads the density emitters' grids again (sim/vdb/volume_loader.h),
// which takes seconds (vdb-cloud: about 1.6 s on the project's machine), and the window keeps running
// meanwhile. Edits accumulate in the editor, so each prepared preset holds every edit before it: one
// is prepared at a time, and of those that come in meanwhile only the latest is kept.
#pragma once

#include "sim/preset.h"

#include <functional>
#include <future>
#include <optional>
#include <string>
#include <utility>

namespace brume::app {

// Whether preparing `preset` converts or reads a density grid (else it is quick and done in place).
bool preparing_is_slow(const Preset& preset);

class PendingEdit {
public:
    PendingEdit() = default;
    PendingEdit(const PendingEdit&) = delete;
    PendingEdit& operator=(const PendingEdit&) = delete;
    // Waits for a preparation still running (its result is dropped).
    ~PendingEdit();

    // Prepares `preset` (read from the edited text; `key`: the edited KEY.PATH) with `prepare` on a
    // worker, after the one running if any. `prepare` must stay valid until this is destroyed.
    void start(Preset preset, std::string key, std::function<void(Preset&)> prepare);
    bool busy() const { return job_.valid() || queued_.has_value(); }
    // The edits being prepared no longer apply (a hot reload replaced the preset): dropped.
    void discard() {
        queued_.reset();
        discard_ = job_.valid();
    }
    // A prepared edit once ready, with its key; nullopt while none is, or with `error` set when
    // preparing failed.
    std::optional<std::pair<Preset, std::string>> poll(std::string& error);

private:
    void launch(Preset preset, std::string key);

    std::function<void(Preset&)> prepare_;
    std::future<Preset> job_;
    std::string job_key_;
    std::optional<std::pair<Preset, std::string>> queued_;
    bool discard_ = false;
};

}  // namespace brume::app
