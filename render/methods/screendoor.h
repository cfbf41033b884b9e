// The `screendoor` method (seed 002: object-space screen-door transparency with supersampling).
//
// Every sphere is drawn as opaque geometry into a colour + depth target S times wider and taller than
// the image, nearest entry distance wins. At each sub-sample the sphere's fragment is kept or
// discarded by comparing its alpha (shaders/sphere_sample.glsl: 1 - exp(-tau * chord), the chord
// clipped by the eye and the opaque surface) with a threshold from a random mask fixed to the
// particle: the mask lies on the particle's camera-facing plane through its centre, one texel per
// sub-sample footprint at the particle's distance (the scale rule of the paper's section 4.2.1), and
// its texels are hashed from (particle index, texel), so the pattern moves with the particle and two
// particles' masks are independent. A kept fragment shows albedo * L_s at full coverage. A box filter
// then averages each S x S block into the HDR target; sub-samples no sphere kept show the opaque
// radiance of their pixel (the opaque pass runs at the image's resolution, so boxes, and the clipping
// of spheres by boxes, are sampled at the pixel centre exactly as the reference samples them).
//
// The expected kept fraction of a sub-sample is alpha, so the image converges, as S grows, to
// "nearest-entry over" compositing of whole spheres, anti-aliased by the box filter: exact (up to
// anti-aliasing at silhouettes) where spheres do not intersect, noisy with a standard deviation of
// about sqrt(alpha (1 - alpha)) / S per layer, and wrong where spheres intersect (the nearer entry
// hides the other sphere's part inside it with probability alpha, whatever the overlap). S = 1 samples
// the reference's pixel-centre rays; an opaque sphere (alpha = 1) is then exact.
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

class ScreendoorMethod : public GpuMethod {
public:
    static constexpr int kDefaultSamples = 4;
    static constexpr int kMaxSamples = 8;
    static constexpr VkFormat kColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // rgb radiance, a: 1 where kept

    // `samples`: S, sub-samples per pixel along each axis, 1 .. kMaxSamples (else std::invalid_argument).
    ScreendoorMethod(vk::Device& device, int samples = kDefaultSamples);

    std::string name() const override { return "screendoor:" + std::to_string(samples_); }
    bool exact() const override { return false; }
    // Throws std::runtime_error when the supersampled targets exceed the device's image size limit or
    // half its device-local memory.

    // The frame path's side (render/frame/gpu_method.h).
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

    int samples() const { return samples_; }
    // Bytes of the supersampled colour + depth targets for an image of width x height.
    static std::uint64_t target_bytes(int samples, std::uint32_t width, std::uint32_t height);

private:
    void ensure_targets(VkExtent2D extent);

    int samples_;
    vk::UniquePipeline sphere_pipeline_;
    vk::UniquePipeline resolve_pipeline_;
    vk::DeviceImage color_;  // S x extent: kept spheres' radiance, a = 1 where a sphere was kept
    vk::DeviceImage depth_;  // S x extent: 1 / (1 + entry distance), nearest wins (GREATER)
    VkExtent2D extent_{};    // the image's extent the targets were made for
};

// `--method screendoor[:S]`, S in 1..8, default 4. Throws std::invalid_argument on a bad setting.
std::unique_ptr<Method> make_screendoor_method(vk::Device& device, const std::string& setting);

}  // namespace brume
