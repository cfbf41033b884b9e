// Encoding a rendered PNG sequence with the ffmpeg command-line tool (Debian package ffmpeg).
#pragma once

#include <filesystem>
#include <string>

namespace brume::app {

// The first line of `ffmpeg -version`, or empty when ffmpeg cannot be run.
std::string ffmpeg_version();

// Encodes frames `pattern` (printf-style, e.g. DIR/plume.%04d.png) numbered first..first+count-1
// at `fps` into `output` (H.264 in MP4, yuv420p so every player opens it). Written to a temporary
// name beside `output` and renamed when complete; ffmpeg's own log goes to `log`, which is removed
// after a good encoding and kept when ffmpeg fails. Throws std::runtime_error with the end of that
// log when ffmpeg fails.
void encode_video(const std::string& pattern, int first, int count, double fps, const std::filesystem::path& output,
                  const std::filesystem::path& log);

}  // namespace brume::app
