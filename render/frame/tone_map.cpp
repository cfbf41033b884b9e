#include "render/frame/tone_map.h"

#include "fullscreen.vert.h"
#include "render/vk/gpu_types.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"
#include "tone_map.frag.h"

#include <cmath>

namespace brume {

using namespace vk;

bool is_srgb_format(VkFormat format) {
    switch (format) {
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_A8B8G8R8_SRGB_PACK32: return true;
    default: return false;
    }
}

ToneMapPass::ToneMapPass(const Device& device, VkFormat format, VkImageLayout final_layout)
    : device_(device), format_(format) {
    VkDevice d = device.get();
    VkAttachmentDescription attachment{};
    attachment.format = format;
    attachment.samples = VK_SAMPLE_COUNT_1_BIT;
    attachment.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // the triangle writes every pixel
    attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachment.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachment.finalLayout = final_layout;
    VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color;
    // The attachment's layout transition waits for the swapchain image (the acquire semaphore's
    // stage) and for the last use of the target.
    VkSubpassDependency before{};
    before.srcSubpass = VK_SUBPASS_EXTERNAL;
    before.dstSubpass = 0;
    before.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    before.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    before.srcAccessMask = 0;
    before.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkSubpassDependency after{};
    after.srcSubpass = 0;
    after.dstSubpass = VK_SUBPASS_EXTERNAL;
    after.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    after.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;
    after.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    const VkSubpassDependency dependencies[] = {before, after};
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &attachment;
    rp.subpassCount = 1;
    rp.pSubpasses = &subpass;
    rp.dependencyCount = 2;
    rp.pDependencies = dependencies;
    VkRenderPass render_pass;
    VK_CHECK(vkCreateRenderPass(d, &rp, nullptr, &render_pass));
    render_pass_ = UniqueRenderPass(d, render_pass);
    device.set_name(VK_OBJECT_TYPE_RENDER_PASS, render_pass, "tone_map.render_pass");

    VkSamplerCreateInfo sampler_info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sampler_info.magFilter = VK_FILTER_NEAREST;
    sampler_info.minFilter = VK_FILTER_NEAREST;
    sampler_info.addressModeU = sampler_info.addressModeV = sampler_info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler;
    VK_CHECK(vkCreateSampler(d, &sampler_info, nullptr, &sampler));
    sampler_ = UniqueSampler(d, sampler);

    VkDescriptorSetLayoutBinding binding{gpu::BINDING_TONE_MAP_HDR, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1,
                                         VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = 1;
    layout_info.pBindings = &binding;
    VkDescriptorSetLayout set_layout;
    VK_CHECK(vkCreateDescriptorSetLayout(d, &layout_info, nullptr, &set_layout));
    set_layout_ = UniqueDescriptorSetLayout(d, set_layout);
    VkPushConstantRange push{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu::ToneMapParams)};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &set_layout;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &push;
    VkPipelineLayout pipeline_layout;
    VK_CHECK(vkCreatePipelineLayout(d, &pl, nullptr, &pipeline_layout));
    pipeline_layout_ = UniquePipelineLayout(d, pipeline_layout);

    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkDescriptorPool pool;
    VK_CHECK(vkCreateDescriptorPool(d, &pool_info, nullptr, &pool));
    pool_ = UniqueDescriptorPool(d, pool);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    VK_CHECK(vkAllocateDescriptorSets(d, &alloc, &set_));

    GraphicsPipelineDesc desc;
    desc.name = "tone_map";
    desc.vertex = BRUME_SPIRV(spv_fullscreen_vert);
    desc.fragment = BRUME_SPIRV(spv_tone_map_frag);
    desc.color_formats = {format};
    desc.fragment_constants = {is_srgb_format(format) ? 0u : 1u};
    desc.render_pass = render_pass;
    pipeline_ = create_graphics_pipeline(device, pipeline_layout, desc);
}

UniqueFramebuffer ToneMapPass::make_framebuffer(VkImageView target, VkExtent2D extent) const {
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = render_pass_;
    info.attachmentCount = 1;
    info.pAttachments = &target;
    info.width = extent.width;
    info.height = extent.height;
    info.layers = 1;
    VkFramebuffer framebuffer;
    VK_CHECK(vkCreateFramebuffer(device_.get(), &info, nullptr, &framebuffer));
    return UniqueFramebuffer(device_.get(), framebuffer);
}

void ToneMapPass::record(VkCommandBuffer cmd, VkFramebuffer framebuffer, VkExtent2D target_extent, VkImageView hdr,
                         VkExtent2D hdr_extent, double exposure_stops,
                         const std::function<void(VkCommandBuffer)>& overlay) {
    if (hdr != bound_hdr_) {
        VkDescriptorImageInfo image{sampler_, hdr, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = set_;
        write.dstBinding = gpu::BINDING_TONE_MAP_HDR;
        write.descriptorCount = 1;
        write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        write.pImageInfo = &image;
        vkUpdateDescriptorSets(device_.get(), 1, &write, 0, nullptr);
        bound_hdr_ = hdr;
    }
    gpu::ToneMapParams params{};
    params.scale.x = float(std::exp2(exposure_stops));
    params.source = gpu::vec4(float(hdr_extent.width) / float(target_extent.width),
                              float(hdr_extent.height) / float(target_extent.height), float(hdr_extent.width),
                              float(hdr_extent.height));

    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = render_pass_;
    begin.framebuffer = framebuffer;
    begin.renderArea = {{0, 0}, target_extent};
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout_, 0, 1, &set_, 0, nullptr);
    vkCmdPushConstants(cmd, pipeline_layout_, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof params, &params);
    set_viewport(cmd, target_extent);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    if (overlay) overlay(cmd);
    vkCmdEndRenderPass(cmd);
}

}  // namespace brume
