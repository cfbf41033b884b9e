// Progress of one long frame (the exact reference's shadows take seconds to minutes a frame) on a
// terminal: after a second, a line redrawn twice a second with the share of pixels done, the time
// taken and an estimate of the time left, cleared when the frame ends. Nothing where the output is
// not a terminal (logs, CI), and nothing for a frame done within the second.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace brume::app {

class FrameProgress {
public:
    // Shows `counter` against `total` (pixels) under `label` while the object lives; the counter
    // starts from 0 here.
    FrameProgress(std::string label, std::uint64_t total, std::atomic<std::uint64_t>& counter,
                  std::FILE* out = stderr);
    ~FrameProgress();
    FrameProgress(const FrameProgress&) = delete;
    FrameProgress& operator=(const FrameProgress&) = delete;

    // The line as it reads after `seconds` with `done` of `total` pixels finished (for the tests).
    static std::string line(const std::string& label, std::uint64_t done, std::uint64_t total, double seconds);

private:
    void run();

    std::string label_;
    std::uint64_t total_;
    std::atomic<std::uint64_t>& counter_;
    std::FILE* out_;
    bool shown_ = false;
    std::mutex mutex_;
    std::condition_variable stop_signal_;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace brume::app
