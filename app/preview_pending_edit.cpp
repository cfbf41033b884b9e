#include "app/preview_pending_edit.h"

#include "app/preview_edit.h"

#include <chrono>
#include <exception>

namespace brume::app {

namespace {

// The key a merged edit is applied with: one the simulator reads wins, since the preset it goes
// with holds that edit too (PreviewSession::apply_edit keeps the simulation only for keys it does
// not read). Two the simulator reads merge into "", which names no single emitter
// (edited_emitter), so the merged edit replays the simulation from the start.
std::string merged_key(const std::string& earlier, const std::string& later) {
    const bool a = edit_affects_simulation(earlier), b = edit_affects_simulation(later);
    if (a && b) return earlier == later ? earlier : "";
    return a ? earlier : later;
}

}  // namespace

bool preparing_is_slow(const Preset& preset) {
    if (!preset.scene.volumes.empty()) return true;
    for (const EmitterDesc& e : preset.emitters)
        if (e.shape == EmitterShape::Density) return true;
    return false;
}

PendingEdit::~PendingEdit() {
    if (job_.valid()) job_.wait();
}

void PendingEdit::launch(Preset preset, std::string key) {
    job_key_ = std::move(key);
    job_ = std::async(std::launch::async, [prepare = prepare_, p = std::move(preset)]() mutable {
        prepare(p);
        return p;
    });
}

void PendingEdit::start(Preset preset, std::string key, std::function<void(Preset&)> prepare) {
    prepare_ = std::move(prepare);
    if (job_.valid()) {
        // A later edit replaces one not yet started.
        std::string k = queued_ ? merged_key(queued_->second, key) : std::move(key);
        queued_.emplace(std::move(preset), std::move(k));
        return;
    }
    launch(std::move(preset), std::move(key));
}

std::optional<std::pair<Preset, std::string>> PendingEdit::poll(std::string& error) {
    if (!job_.valid() || job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
    if (discard_) {
        discard_ = false;
        try {
            (void)job_.get();
        } catch (const std::exception&) {
        }
        if (queued_) {
            auto next = std::move(*queued_);
            queued_.reset();
            launch(std::move(next.first), std::move(next.second));
        }
        return std::nullopt;
    }
    std::optional<std::pair<Preset, std::string>> out;
    try {
        out.emplace(job_.get(), job_key_);
        error.clear();
    } catch (const std::exception& e) {
        error = e.what();
    }
    if (queued_) {
        // The newer edit holds this one's too: it replaces it.
        auto next = std::move(*queued_);
        queued_.reset();
        next.second = merged_key(job_key_, next.second);
        launch(std::move(next.first), std::move(next.second));
        if (out) return std::nullopt;
    }
    return out;
}

}  // namespace brume::app
