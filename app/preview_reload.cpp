#include "app/preview_reload.h"

#include "sim/preset_file.h"
#include "sim/vdb/volume_loader.h"

#include <chrono>
#include <exception>

namespace brume::app {

PresetWatcher::PresetWatcher(std::filesystem::path path, int width, int height)
    : path_(std::move(path)), width_(width), height_(height), last_(stamp()) {}

std::optional<PresetWatcher::Stamp> PresetWatcher::stamp() const {
    std::error_code ec;
    Stamp s;
    s.time = std::filesystem::last_write_time(path_, ec);
    if (ec) return std::nullopt;
    s.size = std::filesystem::file_size(path_, ec);
    if (ec) return std::nullopt;
    return s;
}

PresetWatcher::~PresetWatcher() {
    if (job_.valid()) job_.wait();
}

std::optional<Preset> PresetWatcher::poll(double now_seconds, std::string& error) {
    if (job_.valid()) {
        if (job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
        ++changes_;
        try {
            Preset preset = job_.get();
            error.clear();
            return preset;
        } catch (const std::exception& e) {
            error = e.what();
            return std::nullopt;
        }
    }
    if (last_check_ >= 0.0 && now_seconds - last_check_ < 0.25) return std::nullopt;
    last_check_ = now_seconds;
    const std::optional<Stamp> now = stamp();
    // A file being replaced can be missing for a moment: wait for it to come back.
    if (!now || now == last_) return std::nullopt;
    last_ = now;
    // A change while this read runs is seen by the first check after it is handed over.
    job_ = std::async(std::launch::async, [path = path_, width = width_, height = height_] {
        Preset preset = load_preset_file(path);
        preset.scene.camera.width = width;
        preset.scene.camera.height = height;
        prepare_preset(preset);
        return preset;
    });
    return std::nullopt;
}

}  // namespace brume::app
