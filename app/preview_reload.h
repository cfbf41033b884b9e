// Hot reload: the preview watches the preset or scene file it opened, and when the file changes on
// disk (its modification time or size) reads it again. A file that fails to read leaves the last good
// preset playing and hands back its `file:line: key` error for the panel.
#pragma once

#include "sim/preset.h"

#include <filesystem>
#include <optional>
#include <string>

namespace brume::app {

class PresetWatcher {
public:
    // `path`: the file opened; `width` x `height`: the viewport, which a reload keeps.
    PresetWatcher(std::filesystem::path path, int width, int height);

    // Checks the file (at most every quarter second of the calls' clock): nullopt when it has not
    // changed; otherwise the newly read and prepared preset, or an error in `error`.
    std::optional<Preset> poll(double now_seconds, std::string& error);
    // How many changes were seen (read or refused): a script can wait for the next one.
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
};

}  // namespace brume::app
