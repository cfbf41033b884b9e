// The `peel` method (seed 001 section 3.2, GUIDE section 3): depth peeling of the sphere impostors.
// Each sphere is one homogeneous layer (sphere_sample.glsl: alpha = 1 - exp(-tau * clipped chord),
// colour albedo * L_s), composited front to back ("under"): L += T * alpha * colour, T *= exp(-x).
// That is exact where the spheres' chords do not overlap; where media intersect, peel composites
// whole spheres in order of entry distance instead of mixing them (not the reference).
//
// Keys: per pixel each sphere has the key (t0, sphere index), t0 its clipped entry distance,
// compared as exact floats, the index breaking ties, so coincident spheres and spheres containing
// the eye (t0 = 0) peel one by one, lowest index first.
//
// "peel:N" (default 8, 1..64), classic front-to-back peeling (Everitt 2001): peel pass p keeps the
// fragments whose key is greater than the key pass p-1 peeled and lets the depth test (LESS on
// t0 * 2^-k, exact) pick the smallest; equal depths keep the first drawn, the lowest index. A
// fullscreen composite shades that sphere and puts it under the result so far.
//
// "peel:dual:N" (1..64), dual depth peeling (Bavoil & Myers 2008): a first pass finds each pixel's
// nearest and farthest t0; each of the N passes after it peels the smallest remaining key at the
// front and the largest at the back (MAX blending only: the device does not enable independent
// blend states), and its composite puts the front layer under the front result and the back layer
// in front of the back result. Up to 2N layers in N + 1 geometry passes.
//
// Layers beyond the passes are approximated, not dropped: a tail pass sums every sphere's optical
// depth x and x * colour per pixel; minus what was peeled, that is the tail, composited as one
// homogeneous slab (between the front and the back layers for dual) with optical depth X = sum x
// (so its transmittance exp(-X) is exact) and the x-weighted mean colour (the extinction-weighted
// albedo of GUIDE section 1). Per channel the error against the layer-by-layer result is at most
// T_front * (1 - exp(-X)) * (max - min of the tail layers' colours), T_front the transmittance in
// front of the tail: zero when the tail's layers share one colour. PeelOptions::tail = false drops
// the tail instead.
//
// Early stop: each composite counts the pixels that may hold more layers and, when there are any,
// switches on the next geometry pass (or the tail) in its indirect draw arguments, so passes beyond
// the scene's depth draw nothing; the CPU reads the counts back after every few passes and stops
// recording. The scene's min_transmittance ends a pixel as the reference does (nothing behind is
// added) when the transmittance falls below it after a peeled layer (dual: a front layer). Within
// the tail and dual's back layers it is not applied: what they add beyond that point is less than
// min_transmittance times the radiance there.
//
// FrameStats: `passes` holds "clear+opaque", one entry per peel pass that drew spheres ("peel[p]";
// dual: "window", "dual[p]", each with its composite), "passes switched off" (recorded passes the
// GPU skipped: their attachment clears), "tail", "resolve"; `memory_bytes` the method's images and
// buffers. The list fields stay 0. last_frame() says how many passes were drawn.
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

// "" / "N" / "dual" / "dual:N". Throws std::invalid_argument naming the setting.
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
    // Bound to BINDING_AUX_IMAGE0 + i. classic: keys0, keys1 (ping-pong), tail;
    // dual: state, window, tail, ids.
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
