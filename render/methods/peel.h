// The `peel` method: depth peeling of the sphere impostors (Maule, "Survey on Order Independent
// Transparency Techniques", section 3.2). Each sphere is one layer (sphere_sample.glsl), peeled in
// order of its clipped entry distance (ties: lowest sphere index first) and composited front to back.
// Exact where the spheres' chords do not overlap and the passes reach every layer; intersecting
// media are composited as whole spheres (not the reference).
// Settings: "peel:N" (1..64, default 8), classic peeling (Everitt 2001), one layer per pass;
// "peel:dual:N" (1..64), dual depth peeling (Bavoil & Myers 2008), a front and a back layer per pass,
// up to 2N layers in N + 1 geometry passes. Layers beyond the passes are composited as one slab of
// exact transmittance (PeelOptions::tail = false drops them). Passes beyond the scene's depth are
// switched off on the GPU, and the CPU stops recording once the counts it reads back say so.
// Keys, the tail's error bound, the early stop and the FrameStats pass names: docs/methods.md, peel.
#pragma once

#include "render/frame/gpu_method.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brume {

struct PeelOptions {
    int passes = 8;      // peel passes N, 1..64 (dual: N passes after the window pass)
    bool dual = false;   // dual depth peeling
    bool tail = true;    // approximate the layers beyond the passes (false: drop them; tests)
    int passes_per_submit = 4;  // geometry passes per submission between CPU early-stop checks
};

// "" (the default) / "N" / "dual:N". Throws std::invalid_argument naming the setting ("dual" alone too).
PeelOptions parse_peel_setting(const std::string& setting);

std::unique_ptr<Method> make_peel_method(vk::Device& device, const std::string& setting);

// What the last frame did, beyond FrameStats.
struct PeelFrameInfo {
    int passes_recorded = 0;  // peel passes recorded (dual: including the window pass)
    int passes_drawn = 0;     // of those, passes that drew spheres (the others were switched off on the GPU)
    bool tail_drawn = false;  // layers remained after the last pass somewhere
    // Per recorded pass: pixels that peeled a layer and may have more (classic), or whose window
    // still holds something (dual).
    std::vector<std::uint32_t> pixels_going_on;
};

class PeelMethod : public GpuMethod {
public:
    PeelMethod(vk::Device& device, PeelOptions options);

    std::string name() const override;
    bool exact() const override { return false; }

    const PeelFrameInfo& last_frame() const { return info_; }
    const PeelOptions& options() const { return options_; }

    // The frame path's side (render/frame/gpu_method.h). Each step records passes_per_submit peel
    // passes; after_step reads the early-stop counts and asks for the next step, the last of which
    // records the tail and the resolve.
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    After after_step(FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    void ensure_targets(VkExtent2D extent);
    void record_start(VkCommandBuffer cmd, const FrameContext& ctx);
    void record_pass(VkCommandBuffer cmd, const FrameContext& ctx, int pass);
    void record_finish(VkCommandBuffer cmd, const FrameContext& ctx);
    void record_control_readback(VkCommandBuffer cmd);

    PeelOptions options_;
    int geometry_passes_;  // peel passes P (dual: N + 1); the tail is geometry pass P
    vk::UniquePipeline peel_pipeline_;
    vk::UniquePipeline tail_pipeline_;
    vk::UniquePipeline composite_pipeline_;
    vk::UniquePipeline resolve_pipeline_;
    // classic: keys0, keys1 (ping-pong), tail; dual: state, window, tail, ids. Each is bound to
    // its BINDING_PEEL_* (shaders/shared.h).
    std::vector<vk::DeviceImage> images_;
    vk::DeviceImage depth_;  // classic only
    vk::Buffer accum_;
    vk::Buffer control_;
    vk::Buffer control_readback_;
    VkExtent2D extent_{};
    // This frame's progress: the first pass of the next step, and whether the early stop was taken
    // (the next step records only the tail and the resolve).
    int first_pass_ = 0;
    bool stopping_ = false;
    gpu::PeelControl control_seen_{};  // what the last step's submission read back
    PeelFrameInfo info_;
};

}  // namespace brume
