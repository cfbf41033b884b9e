// Replacing a file so that no failure or interruption loses what was there: every output Brume
// writes (images, statistics, scenes) goes through here.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string_view>

namespace brume {

class FileWriteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Writes `bytes` to a hidden temporary file beside `path`, flushes it to disk and renames it into
// place: readers see either the old file or the complete new one, never a partial one. Throws
// FileWriteError naming the path and the operating system's reason.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Checks that `path` could be written (its directory exists and is a directory, the path is not a
// directory) without touching anything, so a command can refuse before it writes its first output.
// Throws FileWriteError naming the path.
void check_writable_path(const std::filesystem::path& path);

}  // namespace brume
