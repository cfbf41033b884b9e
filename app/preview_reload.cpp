#include "app/preview_reload.h"

#include "sim/preset_file.h"
#include "sim/vdb/volume_loader.h"

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

std::optional<Preset> PresetWatcher::poll(double now_seconds, std::string& error) {
    if (last_check_ >= 0.0 && now_seconds - last_check_ < 0.25) return std::nullopt;
    last_check_ = now_seconds;
    const std::optional<Stamp> now = stamp();
    // A file being replaced can be missing for a moment: wait for it to come back.
    if (!now || now == last_) return std::nullopt;
    last_ = now;
    ++changes_;
    try {
        Preset preset = load_preset_file(path_);
        preset.scene.camera.width = width_;
        preset.scene.camera.height = height_;
        prepare_preset(preset);
        error.clear();
        return preset;
    } catch (const std::exception& e) {
        error = e.what();
        return std::nullopt;
    }
}

}  // namespace brume::app
