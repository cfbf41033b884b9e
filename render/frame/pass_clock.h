// Named GPU passes of one frame: the frame path starts the clock, it and the method mark the end of
// each pass, and the FrameStats list the passes in the order they ran (GPU timestamps).
#pragma once

#include "render/frame/frame_stats.h"
#include "render/vk/device.h"
#include "render/vk/gpu_timer.h"

#include <cstdint>
#include <string>
#include <vector>

namespace brume {

class PassClock {
public:
    // More passes than any method records in a frame (peel:dual:64 records 68).
    static constexpr std::uint32_t kMaxPasses = 255;

    explicit PassClock(const vk::Device& device);
    // Resets the clock and writes the frame's first stamp.
    void start(VkCommandBuffer cmd);
    // Ends the pass named `pass`: its time runs from the previous stamp to this one.
    void mark(VkCommandBuffer cmd, std::string pass);
    // The marked passes and their GPU time (waits for the stamps).
    std::vector<PassTime> passes() const;

private:
    vk::GpuTimer timer_;
    std::vector<std::string> names_;
};

}  // namespace brume
