// `kbuf` (k-buffer; Maule, "Survey on Order Independent Transparency Techniques", sections 2.5
// and 4.2): the k nearest sphere fragments of each pixel kept in k sorted slots (an atomicMin
// insertion chain, as FreePipe does), composited front to back with "over" using
// sphere_sample.glsl's alpha and colour per sphere; the fragments beyond them are composited behind
// as one layer with their exact transmittance and alpha-weighted mean colour.
// Exact for pixels with at most k non-intersecting spheres (or a tail of one colour); intersecting
// spheres are composited as whole spheres. Setting: k, 1..32, default 8 (`--method kbuf:k`).
// Memory: 12 bytes per slot, k slots per pixel; prepare() refuses a slot buffer larger than one
// storage-buffer descriptor. Passes, keys and the tail's error bound: docs/methods.md, kbuf.
#pragma once

#include "render/image.h"
#include "render/frame/frame_resources.h"
#include "render/frame/gpu_method.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <string>

namespace brume {

inline constexpr std::uint32_t kKbufMaxK = 32;
inline constexpr std::uint32_t kKbufDefaultK = 8;

// Parses the setting ("" -> 8, "1".."32"); throws std::invalid_argument naming the problem.
std::uint32_t parse_kbuf_setting(const std::string& setting);

class KBufferMethod : public GpuMethod {
public:
    KBufferMethod(vk::Device& device, std::uint32_t k = kKbufDefaultK);

    std::string name() const override { return "kbuf:" + std::to_string(k_); }
    bool exact() const override { return false; }

    // The frame path's side (render/frame/gpu_method.h). prepare() throws std::runtime_error when
    // the slot buffers exceed the device's storage-buffer range.
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

    std::uint32_t k() const { return k_; }

private:
    void ensure_targets(VkExtent2D extent);

    std::uint32_t k_;
    vk::UniquePipeline keys_pipeline_;
    vk::UniquePipeline payload_pipeline_;
    vk::UniquePipeline resolve_pipeline_;
    vk::Buffer keys_;    // uint per slot, pixel-major (pixel * k + slot); 0xffffffff: empty
    vk::Buffer ids_;     // sphere per slot; 0xffffffff: unclaimed
    vk::Buffer exits_;   // clipped exit distance per slot
    vk::DeviceImage tail_accum_;          // rgba32f: sum(alpha c), sum(alpha) of the tail
    vk::DeviceImage tail_optical_depth_;  // r32f: sum(tau * chord) of the tail
    VkExtent2D extent_{};
};

// `--method kbuf[:k]`, k from 1 to 32, default 8.
std::unique_ptr<Method> make_kbuf_method(vk::Device& device, const std::string& setting);

}  // namespace brume
