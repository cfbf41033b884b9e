// The presenters' pass: samples the frame's HDR target and writes display values into an 8-bit
// target with the PNG writer's exposure and sRGB transfer, so a window shows what `--png` writes.
// It runs inside a VkRenderPass (not dynamic rendering) so that an overlay drawn in the same pass,
// such as Dear ImGui 1.86's Vulkan backend, can share it.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <functional>

namespace brume {

class ToneMapPass {
public:
    // `format`: the target's; *_SRGB formats encode in hardware, UNORM ones in the shader.
    // `final_layout`: where the render pass leaves the target (PRESENT_SRC_KHR for a swapchain).
    ToneMapPass(const vk::Device& device, VkFormat format, VkImageLayout final_layout);

    VkRenderPass render_pass() const { return render_pass_; }
    VkFormat format() const { return format_; }
    vk::UniqueFramebuffer make_framebuffer(VkImageView target, VkExtent2D extent) const;

    // Records the pass into `framebuffer` from `hdr` (SHADER_READ_ONLY_OPTIMAL), with `exposure_stops`;
    // `overlay` records more draws inside the same render pass. The HDR view is written into the
    // pass's descriptor set when it changes, which must not happen while a frame using it is in flight.
    void record(VkCommandBuffer cmd, VkFramebuffer framebuffer, VkExtent2D target_extent, VkImageView hdr,
                VkExtent2D hdr_extent, double exposure_stops,
                const std::function<void(VkCommandBuffer)>& overlay = {});

private:
    const vk::Device& device_;
    VkFormat format_;
    vk::UniqueRenderPass render_pass_;
    vk::UniqueSampler sampler_;
    vk::UniqueDescriptorSetLayout set_layout_;
    vk::UniquePipelineLayout pipeline_layout_;
    vk::UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    vk::UniquePipeline pipeline_;
    VkImageView bound_hdr_ = VK_NULL_HANDLE;
};

// Whether a target of `format` gets its sRGB encoding from the hardware.
bool is_srgb_format(VkFormat format);

}  // namespace brume
