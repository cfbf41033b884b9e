// The `screendoor` method: object-space screen-door transparency with supersampling (Sen,
// Chemudugunta & Gopi, "Silhouette-Opaque Transparency Rendering"). Spheres are drawn as opaque
// geometry into a target S x S times the image's size, each sub-sample kept where the sphere's alpha
// (sphere_sample.glsl) exceeds a random mask fixed to the particle, nearest entry winning; a box
// filter averages each S x S block.
// It converges, as S grows, to "over" compositing of whole spheres in order of entry distance
// (wrong where spheres intersect); S = 1 samples the reference's rays, and an opaque sphere is then
// exact. Setting: S, 1..8, default 4. The mask, the noise and the convergence: docs/methods.md,
// screendoor.
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
// "" (the default), or S as digits, 1 .. kMaxSamples; else std::invalid_argument.
int parse_screendoor_setting(const std::string& setting);
std::unique_ptr<Method> make_screendoor_method(vk::Device& device, const std::string& setting);

}  // namespace brume
