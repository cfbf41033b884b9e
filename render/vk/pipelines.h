// Shader modules from embedded SPIR-V, and the few graphics pipelines Brume's passes need:
// no vertex input (impostors read their storage buffers), dynamic rendering, dynamic viewport.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace brume::vk {

struct Spirv {
    const std::uint32_t* code;
    std::size_t bytes;
};
// BRUME_SPIRV(spv_ppll_resolve_frag) for an array embedded by shaders/CMakeLists.txt.
#define BRUME_SPIRV(array) ::brume::vk::Spirv{array, sizeof(array)}

struct GraphicsPipelineDesc {
    std::string name;
    Spirv vertex{};
    Spirv fragment{};
    std::vector<VkFormat> color_formats;  // may be empty: a pass with no attachments
    VkFormat depth_format = VK_FORMAT_UNDEFINED;
    VkCompareOp depth_compare = VK_COMPARE_OP_ALWAYS;
    bool depth_write = true;  // with a depth format
    // One per colour attachment; empty: no blending, all channels written.
    std::vector<VkPipelineColorBlendAttachmentState> blends;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    bool sample_shading = false;  // run the fragment shader per sample (with samples > 1)
    std::vector<std::uint32_t> fragment_constants;  // specialization constants 0, 1, ... (uint)
    // Subpass 0 of this render pass instead of dynamic rendering into color_formats (the presenter's
    // pass, which Dear ImGui 1.86's Vulkan backend also draws into).
    VkRenderPass render_pass = VK_NULL_HANDLE;
};

// Blend states for the common cases.
VkPipelineColorBlendAttachmentState blend_none();
// dst = src + (1 - src.a) * dst for premultiplied colour ("over"): back-to-front compositing.
VkPipelineColorBlendAttachmentState blend_premultiplied_over();
// dst = src + dst: accumulation (weighted sums).
VkPipelineColorBlendAttachmentState blend_additive();
// dst = max(src, dst) per channel: per-pixel maxima (dual depth peeling's depth range).
VkPipelineColorBlendAttachmentState blend_max();
// dst = dst * (1 - src) per channel, alpha likewise with src alpha: products of transmittances.
// (No pass uses it now: wboit accumulates the optical depth instead, docs/methods.md.)
VkPipelineColorBlendAttachmentState blend_multiply_one_minus_src();

UniqueShaderModule create_shader_module(const Device& device, Spirv spirv, const std::string& name);
UniquePipeline create_graphics_pipeline(const Device& device, VkPipelineLayout layout, const GraphicsPipelineDesc& desc);

// A compute pipeline; `constants` are specialization constants 0, 1, ... (uint).
UniquePipeline create_compute_pipeline(const Device& device, VkPipelineLayout layout, const std::string& name,
                                       Spirv compute, const std::vector<std::uint32_t>& constants = {});

// Viewport and scissor covering `extent` (both are dynamic state in every Brume pipeline).
void set_viewport(VkCommandBuffer cmd, VkExtent2D extent);

}  // namespace brume::vk
