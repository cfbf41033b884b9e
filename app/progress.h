// Progress of a frame sequence: a redrawn bar with frame count, fps and ETA on a terminal, plain
// lines otherwise (logs, CI, job schedulers).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace brume::app {

class Progress {
public:
    Progress(std::string label, int total, std::FILE* out = stdout);
    // Call after each finished frame; `detail` is shown after the figures (e.g. the particle count).
    void frame_done(int frame_index, const std::string& detail);
    void finish();
    double elapsed_seconds() const;

private:
    std::string label_;
    int total_;
    int done_ = 0;
    std::FILE* out_;
    bool terminal_;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace brume::app
