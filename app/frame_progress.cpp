#include "app/frame_progress.h"

#include <unistd.h>

#include <chrono>
#include <cmath>

namespace brume::app {

FrameProgress::FrameProgress(std::string label, std::uint64_t total, std::atomic<std::uint64_t>& counter,
                             std::FILE* out)
    : label_(std::move(label)), total_(total), counter_(counter), out_(out) {
    counter_.store(0, std::memory_order_relaxed);
    if (::isatty(::fileno(out_)) != 0 && total_ > 0) thread_ = std::thread([this] { run(); });
}

FrameProgress::~FrameProgress() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    stop_signal_.notify_one();
    thread_.join();
    if (shown_) {
        std::fprintf(out_, "\r\033[K");  // cleared for what the command prints next
        std::fflush(out_);
    }
}

std::string FrameProgress::line(const std::string& label, std::uint64_t done, std::uint64_t total, double seconds) {
    const double share = total > 0 ? double(done) / double(total) : 1.0;
    char text[160];
    if (done == 0) {
        std::snprintf(text, sizeof text, "%s: 0%% of %llu pixels, %.0f s", label.c_str(), (unsigned long long)total,
                      seconds);
    } else {
        // Tiles differ in cost (empty sky against dense smoke), so the estimate is a rough one.
        const double left = seconds * (1.0 - share) / share;
        std::snprintf(text, sizeof text, "%s: %.0f%% of %llu pixels, %.0f s, about %.0f s left", label.c_str(),
                      std::floor(100.0 * share), (unsigned long long)total, seconds, left);
    }
    return text;
}

void FrameProgress::run() {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_);
    // Quiet for the first second: most frames are done by then.
    if (stop_signal_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; })) return;
    do {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const std::string text = line(label_, counter_.load(std::memory_order_relaxed), total_, seconds);
        std::fprintf(out_, "\r%s\033[K", text.c_str());
        std::fflush(out_);
        shown_ = true;
    } while (!stop_signal_.wait_for(lock, std::chrono::milliseconds(500), [this] { return stop_; }));
}

}  // namespace brume::app
