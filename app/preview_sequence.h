// "Render sequence" from the preview: `brume play` itself renders the frames, in a child process
// started from this executable with the preview's options (the preset as edited, the viewport's size,
// the method, the exposure, the formats), so the files are byte for byte what `brume play` with those
// options writes, and the window keeps running meanwhile: the child has its own device and threads.
// Progress is read from the child's progress lines (app/progress.h), which go to a log file.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace brume::app {

class SequenceRender {
public:
    SequenceRender() = default;
    SequenceRender(const SequenceRender&) = delete;
    SequenceRender& operator=(const SequenceRender&) = delete;
    // A render still running is asked to stop (SIGTERM: play finishes the frame it is on) and
    // waited for.
    ~SequenceRender();

    // Starts `brume play` with `play_args` (everything after "play"), `frames` frames; `temporary`
    // (may be empty) is removed when it ends. Throws std::runtime_error when one is running or the
    // process cannot start.
    void start(const std::vector<std::string>& play_args, int frames, std::filesystem::path temporary = {});
    // Collects the child once it exited and reads its progress. Cheap; call once a frame.
    void poll();
    bool running() const { return pid_ > 0; }
    int frames_done() const { return done_; }
    int frames_total() const { return total_; }
    // After it ended: play's exit status (-1 before any run), and its summary line ("wrote N frames ..."),
    // or its last line when it has none (an error).
    int status() const { return status_; }
    const std::string& last_line() const { return last_line_; }
    const std::filesystem::path& log() const { return log_; }

private:
    void read_log();

    pid_t pid_ = -1;
    int done_ = 0, total_ = 0, status_ = -1;
    std::string last_line_;
    std::filesystem::path log_;
    std::filesystem::path temporary_;
};

}  // namespace brume::app
