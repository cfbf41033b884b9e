// GPU timestamps between passes. Stamps are written at bottom-of-pipe: lavapipe's top-of-pipe
// stamps do not wait for earlier work and read wrong (docs/performance.md's figures are taken so).
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstdint>
#include <vector>

namespace brume::vk {

class GpuTimer {
public:
    GpuTimer(const Device& device, std::uint32_t max_stamps, const char* name);
    void reset(VkCommandBuffer cmd);                    // record before the first stamp of a frame
    void stamp(VkCommandBuffer cmd, std::uint32_t index);  // after the work it ends
    // Milliseconds between consecutive stamps 0..count-1 of the last submitted frame (waits for them).
    std::vector<double> intervals_ms(std::uint32_t count) const;

private:
    const Device& device_;
    UniqueQueryPool pool_;
    std::uint32_t max_stamps_;
    double ns_per_tick_;
    std::uint64_t valid_mask_;
};

}  // namespace brume::vk
