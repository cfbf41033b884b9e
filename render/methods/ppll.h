// The `ppll` method (Barta & Kovács, "Order Independent Transparency with Per-Pixel Linked Lists"):
// per-pixel linked lists of sphere intervals built by an impostor pass, then sorted and integrated
// exactly per pixel. The spheres are drawn far to near, so each list arrives nearly sorted and the
// resolve merges it in one walk, checking the order as it goes (shaders/ppll_resolve.frag) (the light model of docs/methods.md; what "exact" means: docs/accuracy.md). The
// node pool is sized from the scene, checked after every frame, and grown (frame rendered again) on
// overflow up to a budget.
#pragma once

#include "render/frame/gpu_method.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace brume {

struct PpllOptions {
    std::uint64_t max_pool_bytes = 0;  // node-pool budget; 0: half the device-local heap (capped by the parts)
    std::uint64_t initial_nodes = 0;   // first pool size; 0: estimated from the scene's projected spheres
    std::uint64_t part_nodes = 0;      // nodes per pool part, a power of two; 0: the most one
                                       // storage-buffer descriptor can address (tests use small parts)
    bool ordered_path = true;          // false: every pixel by the general path (`ppll-general`)
};

// A pixel's list could not be resolved on this device: its shader loops were cut short (lavapipe
// ends a shader's loops after 65,535 iterations in all). The frame is refused, never written wrong.
class ListResolveError : public std::runtime_error {
public:
    // `longest`: the longest list in nodes, or with `tiles` the most spheres in one tile (tiles method).
    ListResolveError(std::uint64_t pixels, std::uint32_t longest, bool tiles = false);
};

// The scene needs more list memory than the budget allows.
class PoolBudgetError : public std::runtime_error {
public:
    // `addressable` when the limit is what the pool parts can address rather than the budget.
    PoolBudgetError(std::uint64_t needed, std::uint64_t allowed, bool addressable = false);
    std::uint64_t bytes_needed() const { return needed_; }
    std::uint64_t bytes_allowed() const { return allowed_; }

private:
    std::uint64_t needed_, allowed_;
};

// Fragments (list nodes) a scene will need: the projected area of each sphere. An estimate (it
// ignores occlusion by boxes and the eye's clipping), used only to size the first pool.
std::uint64_t estimate_fragments(const Scene& scene);

class PpllMethod : public GpuMethod {
public:
    explicit PpllMethod(vk::Device& device, PpllOptions options = {});

    std::string name() const override { return options_.ordered_path ? "ppll" : "ppll-general"; }
    bool exact() const override { return true; }
    using GpuMethod::render;
    // Renders one frame and reads it back. Throws PoolBudgetError when the lists cannot fit.
    // With `stats`, GPU times and pool figures are filled in; the list-length statistics
    // (max_list_length, nonempty_pixels, ...) cost extra atomics and are gathered only when
    // `list_stats` is also set (render(scene, stats) sets it).
    Image render(const Scene& scene, FrameStats* stats, bool list_stats);

    std::uint64_t max_pool_nodes() const { return max_nodes_; }
    std::uint64_t pool_capacity() const { return capacity_; }

    // The frame path's side (render/frame/gpu_method.h).
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

private:
    void ensure_pipelines(std::uint32_t pool_parts, bool accurate_shadows);
    void ensure_heads(VkExtent2D extent);
    void allocate_pool(std::uint64_t nodes);
    void write_pool_uniforms(FrameContext& ctx) const;
    void upload_draw_order(const Scene& scene);

    PpllOptions options_;
    vk::UniquePipeline append_pipeline_;
    vk::UniquePipeline resolve_pipeline_;
    vk::Buffer heads_;
    vk::Buffer counters_;
    vk::Buffer counters_readback_;
    std::vector<vk::Buffer> pool_parts_;
    std::uint32_t pipeline_parts_ = 0;  // pool parts the pipelines were specialised for
    bool pipeline_accurate_ = false;    // ... and whether for the accurate shadow technique
    std::uint32_t part_shift_ = 0;      // log2(nodes per part)
    std::uint64_t capacity_ = 0;    // nodes
    std::uint64_t max_nodes_ = 0;
    std::uint64_t max_pool_bytes_ = 0;
    gpu::ListCounters counters_seen_{};  // what the last submission counted
    // The draw order, far to near by each sphere's nearest possible distance (less a float margin),
    // and those bounds: the resolve's watermark (shaders/ppll_resolve.frag).
    std::vector<std::uint32_t> order_;
    std::vector<double> bound_;
    vk::Buffer order_buffer_;
    vk::Buffer bound_buffer_;
    double sort_ms_ = 0.0;
};

}  // namespace brume
