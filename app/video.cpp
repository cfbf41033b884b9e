#include "app/video.h"

#include "app/process.h"
#include "render/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace brume::app {
namespace {

// The log's last non-empty line, bounded: ffmpeg's own reason (an unknown encoder, a full disk), carried
// on the one error line every failure gets; the whole log stays on disk.
std::string last_line_of(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::string last;
    for (std::string line; std::getline(in, line);)
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    constexpr std::size_t kMaxEchoed = 300;
    if (last.size() > kMaxEchoed) last = last.substr(0, kMaxEchoed) + "...";
    return last.empty() ? "(nothing)" : "\"" + last + "\"";
}

}  // namespace

std::string ffmpeg_version() {
    // A TMPDIR that names no folder is no reason to say ffmpeg is missing, nor to fail.
    std::error_code ec;
    std::filesystem::path temp_dir = std::filesystem::temp_directory_path(ec);
    if (ec || !std::filesystem::is_directory(temp_dir, ec)) temp_dir = "/tmp";
    const std::string log = temp_dir / ("brume-ffmpeg-probe-" + std::to_string(::getpid()));
    if (run_process({"ffmpeg", "-hide_banner", "-version"}, log) != 0) {
        std::filesystem::remove(log, ec);
        return "";
    }
    std::ifstream in(log);
    std::string first;
    std::getline(in, first);
    in.close();
    std::filesystem::remove(log, ec);
    return first;
}

void encode_video(const std::string& pattern, int first, int count, double fps, const std::filesystem::path& output,
                  const std::filesystem::path& log) {
    // Hidden, beside the output, keeping its extension (ffmpeg picks the container from it). Brume
    // creates and locks it, ffmpeg writes into it: a run killed outright leaves it unlocked, and the
    // next run's cleanup removes it (render/atomic_file.h).
    // What stands at the output decides how the video gets there, as for every output
    // (render/atomic_file.h): a regular file is replaced by a rename and keeps its permissions, a FIFO
    // or a device is written into, a symlink is followed. ffmpeg itself writes a regular temporary file.
    const OutputTarget target = resolve_output(output);
    remove_stale_temporaries(output);
    std::filesystem::path temp;
    const int lock = create_locked_temporary(output, output.extension().string(), temp);
    struct Unlock {
        int fd;
        ~Unlock() { ::close(fd); }
    } unlock{lock};
    struct stat old {};
    if (!target.in_place && ::stat(target.path.c_str(), &old) == 0 && S_ISREG(old.st_mode))
        (void)::fchmod(lock, old.st_mode & 07777);  // ffmpeg truncates the file it is given and keeps its mode
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g", fps);
    const std::vector<std::string> args = {
        "ffmpeg", "-hide_banner", "-y", "-framerate", rate, "-start_number", std::to_string(first), "-i", pattern,
        "-frames:v", std::to_string(count), "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18",
        // H.264 in yuv420p needs even sizes: pad by one pixel where the frame is odd.
        "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", temp.string()};
    const int status = run_process(args, log.string());
    if (status != 0) {
        std::error_code ec;
        std::filesystem::remove(temp, ec);
        throw std::runtime_error("ffmpeg failed (" + (status < 0 ? std::string("could not start") : "exit " + std::to_string(status)) +
                                 ") encoding " + output.string() + "; its log " + log.string() + " ends with " + last_line_of(log));
    }
    std::error_code ec;
    if (target.in_place || target.descriptor >= 0) {
        // A FIFO or device takes the finished file's bytes: it cannot be renamed over.
        std::ifstream in(temp, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        in.close();
        std::filesystem::remove(temp, ec);
        write_file_atomically(output, bytes);
    } else {
        std::filesystem::rename(temp, target.path, ec);
        if (ec) {
            std::filesystem::remove(temp, ec);
            throw std::runtime_error("cannot write " + output.string() + ": " + ec.message());
        }
    }
    // The log is for a failed encoding; after a good one it would only clutter the frames.
    std::filesystem::remove(log, ec);
}

}  // namespace brume::app
