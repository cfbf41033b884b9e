// The `tiles` method: the exact resolve without per-pixel lists, in compute. The host sorts the
// spheres near to far by their nearest bound (render/nearest_bounds.h) and lists them per 8x8-pixel
// tile (render/tile_bins.h); one workgroup per tile intersects each pixel's ray with its tile's
// spheres in that order and merges the events in two small register windows, proving the order as
// it goes and falling back to repeated walks where it cannot (shaders/tiles_resolve.comp).
//
// Against ppll: no fragment atomics, no node pool, no pointer chasing, and no rasterisation (what a
// compute GPU such as an H100/H200 has little of); each sphere of a tile is one broadcast read for
// all its pixels. It costs a CPU binning pass, and per pixel a test of every sphere of its tile,
// hit or not. Memory is sized from the scene each frame: 8 bytes per (sphere, tile) pair.
#pragma once

#include "render/frame/gpu_method.h"
#include "render/tile_bins.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "shaders/shared.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace brume {

struct TilesOptions {
    std::uint64_t max_bytes = 0;  // tile lists and result budget; 0: half the device-local heap
};

// The tile lists of a scene would take more than the budget.
class TileBudgetError : public std::runtime_error {
public:
    TileBudgetError(std::uint64_t needed, std::uint64_t allowed);
};

class TilesMethod : public GpuMethod {
public:
    explicit TilesMethod(vk::Device& device, TilesOptions options = {});

    std::string name() const override { return "tiles"; }
    bool exact() const override { return true; }
    using GpuMethod::render;

    bool has_list_stats() const override { return true; }
    // Under the accurate technique the resolve takes the sun from the depth map alone: the exact
    // integrator's accurate branch never reads the spheres' T_sun at their centres, which the frame
    // path would otherwise work out on the CPU for every frame (ensure_sphere_sun: 9.6 ms of a
    // vdb-cloud preview frame). Set by prepare(), as the frame path asks after it.
    bool reads_sphere_sun() const override { return !pipeline_accurate_; }
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    After after_step(FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

    const TileBins& bins() const { return bins_; }

private:
    void ensure_pipelines(bool accurate_shadows);
    void upload_bins(VkExtent2D extent);

    TilesOptions options_;
    std::uint64_t max_bytes_ = 0;
    vk::UniquePipeline resolve_pipeline_;
    vk::UniquePipeline composite_pipeline_;
    bool pipelines_made_ = false, pipeline_accurate_ = false;
    vk::Buffer counters_;
    vk::Buffer counters_readback_;
    vk::Buffer first_buffer_;
    vk::Buffer entry_buffer_;
    vk::Buffer result_buffer_;
    gpu::ListCounters counters_seen_{};
    std::vector<std::uint32_t> order_;  // far to near (sort_back_to_front), last frame's order reused
    std::vector<std::uint32_t> near_to_far_;
    std::vector<double> bound_;
    TileBins bins_;
    double sort_ms_ = 0.0, bin_ms_ = 0.0;
};

}  // namespace brume
