// `kbuf` (seed 001 sections 2.5 and 4.2): a k-buffer of at most k entries per pixel, in the style of
// FreePipe's "multi depth test" scheme (a fixed, sorted slot array per pixel filled by an atomicMin
// insertion chain), then a resolve that composites the entries front to back with "over", using
// sphere_sample.glsl's alpha and colour per sphere.
//
// Each sphere fragment is one entry (its clipped interval along the pixel ray). Passes:
//   1. keys:    the fragment's key (its unclipped entry distance, as order-preserving bits) is pushed
//               into the pixel's k sorted slots by a chain of atomicMin: the slot keeps the smaller
//               key, the larger one moves on to the next slot, and what leaves slot k-1 is dropped.
//               Slots only ever decrease and stay sorted, so a plain read that finds a slot <= key
//               lets the chain start past it: one read of slot k-1 settles most fragments of deep
//               pixels, a binary search finds the start for the others. Afterwards the slots hold
//               the k smallest keys of the pixel, sorted.
//   2. payload: the same fragments again; each finds its key among the slots (binary search) and
//               claims a slot with that key by atomicCompSwap of the sphere id (ties: one slot per
//               fragment), storing its exit distance. A fragment that finds no slot (its key is
//               beyond slot k-1, or every slot with its key is taken) is in the tail and is blended
//               additively into two targets: sum(alpha c), sum(alpha) and the optical depth
//               sum(tau * chord).
//   3. resolve: walks the k slots in order (no sort: they are sorted) and composites
//               L += T alpha_i c_i, T *= 1 - alpha_i, stopping like the reference once T falls below
//               the scene's min_transmittance; then the tail as one layer behind.
// Keys are 32 bits and the sphere id is separate, so two spheres with bit-identical entry distances
// are kept in either order (only coincident spheres do that; the eye-inside case is ordered by the
// unclipped entry, which is negative and distinct).
//
// Tail approximation: the fragments beyond the k nearest are one layer with
//   alpha_tail = 1 - prod_tail(1 - alpha_j) = 1 - exp(-sum tau_j chord_j),
//   c_tail     = sum_tail(alpha_j c_j) / sum_tail(alpha_j),
// composited behind the k entries. Bound: for non-intersecting spheres the only error is the tail's
// colour weighting (its transmittance prod(1 - alpha_j) is exact), so per pixel and channel
//   |kbuf - exact| <= T_k * alpha_tail * (max_tail c_j - min_tail c_j),
// T_k being the transmittance after the k kept entries. kbuf is therefore exact for pixels with at
// most k non-intersecting spheres (or a tail of one colour). Intersecting spheres are composited as
// whole spheres, the approximation every compositing method shares.
//
// Memory: 12 bytes per slot (key, sphere id, exit distance in three buffers), k slots per pixel; each
// buffer must fit one storage-buffer descriptor (128 MiB on lavapipe: k = 32 up to 1280x720 and more).
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
