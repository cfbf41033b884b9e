// What one frame of a GPU method measured: the time of each pass and the list statistics.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace brume {

struct PassTime {
    std::string name;
    double ms = 0.0;
};

struct FrameStats {
    // Each pass in order: GPU time, or for a pass named "... (cpu)" the CPU's wall clock of work the
    // GPU passes wait for (a method's sort, the light's preparation: FramePath::run).
    std::vector<PassTime> passes;
    double total_ms = 0.0;  // the whole frame: the sum of the passes
    std::uint64_t memory_bytes = 0;  // GPU memory the method holds beyond the shared frame targets
    std::uint64_t fragments = 0;   // list nodes written: one per (sphere, pixel) whose ray meets the medium
    std::uint64_t pool_capacity = 0;  // nodes the pool holds
    std::uint64_t pool_bytes = 0;
    int regrows = 0;  // times this frame was rendered again: after ppll's pool overflowed, or by auto's next path after one refused it
    bool list_stats = false;            // whether the four list figures below were gathered
    std::uint32_t max_list_length = 0;  // nodes in the longest list
    double mean_list_length = 0.0;      // nodes per pixel with a non-empty list
    std::uint64_t nonempty_pixels = 0;
    std::uint64_t long_list_pixels = 0;  // lists that needed more than one resolve window
};

}  // namespace brume
