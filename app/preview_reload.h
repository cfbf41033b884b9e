// Hot reload: the preview watches the preset or scene file it opened, and when the file changes on
// disk (its modification time or size) reads it again. A file that fails to read leaves the last good
// preset playing and hands back its `file:line: key` error for the panel. The file is read and
// prepared (a density grid converted to spheres can take seconds) on a worker thread, so the window
// keeps running meanwhile; poll() hands the result over once it is ready.
#pragma once

#include "sim/preset.h"

#include <filesystem>
#include <future>
#include <optional>
#include <string>

namespace brume::app {

class PresetWatcher {
public:
    // `path`: the file opened; `width` x `height`: the viewport, which a reload keeps.
    PresetWatcher(std::filesystem::path path, int width, int height);

    // Waits for a read still running (its result is dropped).
    ~PresetWatcher();
    // Checks the file (at most every quarter second of the calls' clock) and starts reading it on a
    // worker when it changed. nullopt while nothing new is ready; otherwise the newly read and
    // prepared preset, or nullopt with an error in `error`.
    std::optional<Preset> poll(double now_seconds, std::string& error);
    // Whether a changed file is being read now.
    bool reading() const { return job_.valid(); }
    // How many changes were read or refused: a script can wait for the next one.
    int changes() const { return changes_; }
    const std::filesystem::path& path() const { return path_; }

private:
    struct Stamp {
        std::filesystem::file_time_type time{};
        std::uintmax_t size = 0;
        bool operator==(const Stamp&) const = default;
    };
    std::optional<Stamp> stamp() const;

    std::filesystem::path path_;
    int width_, height_;
    std::optional<Stamp> last_;
    double last_check_ = -1.0;
    int changes_ = 0;
    std::future<Preset> job_;
};

}  // namespace brume::app
