// "Error against the reference" for the frame shown: the CPU reference renderer runs on a worker
// thread at a reduced resolution (the panel says which), and the method's frame of the same scene
// at that resolution is compared with it once it is ready. The window keeps running meanwhile.
#pragma once

#include "render/image.h"
#include "sim/scene.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <optional>
#include <string>

namespace brume::app {

struct ReferenceError {
    int frame = 0;
    std::string method;
    int width = 0, height = 0;
    double max_of_peak = 0.0;   // largest |method - reference| over channels, over the reference's peak
    double rmse_of_peak = 0.0;  // root mean square difference over the peak
    double psnr_db = 0.0;
    double seconds = 0.0;       // the reference's wall-clock time
};

class ReferenceCheck {
public:
    // The largest side the reference renders at; the frame is scaled down to fit.
    static constexpr int kMaxSide = 320;

    ~ReferenceCheck();

    // The reduced size for a viewport of width x height.
    static void reduced_size(int width, int height, int& out_width, int& out_height);
    // Starts the reference of `scene` (already at the reduced size) and its comparison with `method_image`,
    // the method's frame of that scene. False while a check is still running.
    bool start(const Scene& scene, Image method_image, int frame, const std::string& method);
    bool running() const { return job_.valid(); }
    // The running check's share of pixels done, 0 to 1 (ReferenceOptions::pixels_done).
    double share_done() const {
        return pixels_total_ > 0 ? double(pixels_done_.load(std::memory_order_relaxed)) / double(pixels_total_) : 0.0;
    }
    // Collects a finished check; its result stays in last().
    void poll();
    const std::optional<ReferenceError>& last() const { return last_; }
    const std::string& error() const { return error_; }

private:
    std::future<ReferenceError> job_;
    std::atomic<std::uint64_t> pixels_done_{0};  // the job's reference counts into it
    std::uint64_t pixels_total_ = 0;
    std::optional<ReferenceError> last_;
    std::string error_;
};

}  // namespace brume::app
