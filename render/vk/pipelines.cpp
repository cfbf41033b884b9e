#include "render/vk/pipelines.h"

#include "render/vk/vk_check.h"

namespace brume::vk {

UniqueShaderModule create_shader_module(const Device& device, Spirv spirv, const std::string& name) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.bytes;
    info.pCode = spirv.code;
    VkShaderModule module;
    VK_CHECK(vkCreateShaderModule(device.get(), &info, nullptr, &module));
    device.set_name(VK_OBJECT_TYPE_SHADER_MODULE, module, name.c_str());
    return UniqueShaderModule(device.get(), module);
}

UniquePipeline create_graphics_pipeline(const Device& device, VkPipelineLayout layout, const GraphicsPipelineDesc& desc) {
    UniqueShaderModule vs = create_shader_module(device, desc.vertex, desc.name + ".vert");
    UniqueShaderModule fs = create_shader_module(device, desc.fragment, desc.name + ".frag");

    std::vector<VkSpecializationMapEntry> entries;
    for (std::uint32_t i = 0; i < desc.fragment_constants.size(); ++i)
        entries.push_back({i, std::uint32_t(i * sizeof(std::uint32_t)), sizeof(std::uint32_t)});
    VkSpecializationInfo specialization{std::uint32_t(entries.size()), entries.data(),
                                        desc.fragment_constants.size() * sizeof(std::uint32_t),
                                        desc.fragment_constants.data()};

    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vs;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fs;
    stages[1].pName = "main";
    stages[1].pSpecializationInfo = entries.empty() ? nullptr : &specialization;

    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;  // impostor rectangles may come out either way round
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = desc.samples;
    multisample.sampleShadingEnable = desc.sample_shading;
    multisample.minSampleShading = desc.sample_shading ? 1.0f : 0.0f;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    const bool has_depth = desc.depth_format != VK_FORMAT_UNDEFINED;
    depth.depthTestEnable = has_depth;
    depth.depthWriteEnable = has_depth && desc.depth_write;
    depth.depthCompareOp = desc.depth_compare;
    std::vector<VkPipelineColorBlendAttachmentState> blends = desc.blends;
    if (blends.empty()) blends.assign(desc.color_formats.size(), blend_none());
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = std::uint32_t(blends.size());
    blend.pAttachments = blends.data();
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;

    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = std::uint32_t(desc.color_formats.size());
    rendering.pColorAttachmentFormats = desc.color_formats.data();
    rendering.depthAttachmentFormat = desc.depth_format;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
                                      desc.render_pass ? nullptr : &rendering};
    info.renderPass = desc.render_pass;
    info.subpass = 0;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    VkPipeline pipeline;
    VK_CHECK(vkCreateGraphicsPipelines(device.get(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    device.set_name(VK_OBJECT_TYPE_PIPELINE, pipeline, desc.name.c_str());
    return UniquePipeline(device.get(), pipeline);
}

UniquePipeline create_compute_pipeline(const Device& device, VkPipelineLayout layout, const std::string& name,
                                       Spirv compute, const std::vector<std::uint32_t>& constants) {
    UniqueShaderModule cs = create_shader_module(device, compute, name + ".comp");
    std::vector<VkSpecializationMapEntry> entries;
    for (std::uint32_t i = 0; i < constants.size(); ++i)
        entries.push_back({i, std::uint32_t(i * sizeof(std::uint32_t)), sizeof(std::uint32_t)});
    VkSpecializationInfo specialization{std::uint32_t(entries.size()), entries.data(),
                                        constants.size() * sizeof(std::uint32_t), constants.data()};
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = cs.get();
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = entries.empty() ? nullptr : &specialization;
    info.layout = layout;
    VkPipeline pipeline;
    VK_CHECK(vkCreateComputePipelines(device.get(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    device.set_name(VK_OBJECT_TYPE_PIPELINE, pipeline, name.c_str());
    return UniquePipeline(device.get(), pipeline);
}

namespace {
constexpr VkColorComponentFlags kAllChannels =
    VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
}  // namespace

VkPipelineColorBlendAttachmentState blend_none() {
    VkPipelineColorBlendAttachmentState b{};
    b.colorWriteMask = kAllChannels;
    return b;
}

VkPipelineColorBlendAttachmentState blend_premultiplied_over() {
    VkPipelineColorBlendAttachmentState b = blend_none();
    b.blendEnable = VK_TRUE;
    b.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
    b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    b.colorBlendOp = VK_BLEND_OP_ADD;
    b.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    b.alphaBlendOp = VK_BLEND_OP_ADD;
    return b;
}

VkPipelineColorBlendAttachmentState blend_additive() {
    VkPipelineColorBlendAttachmentState b = blend_none();
    b.blendEnable = VK_TRUE;
    b.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
    b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
    b.colorBlendOp = VK_BLEND_OP_ADD;
    b.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    b.alphaBlendOp = VK_BLEND_OP_ADD;
    return b;
}

VkPipelineColorBlendAttachmentState blend_max() {
    VkPipelineColorBlendAttachmentState b = blend_additive();
    b.colorBlendOp = VK_BLEND_OP_MAX;
    b.alphaBlendOp = VK_BLEND_OP_MAX;
    return b;
}

VkPipelineColorBlendAttachmentState blend_multiply_one_minus_src() {
    VkPipelineColorBlendAttachmentState b = blend_none();
    b.blendEnable = VK_TRUE;
    b.srcColorBlendFactor = VK_BLEND_FACTOR_ZERO;
    b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_COLOR;
    b.colorBlendOp = VK_BLEND_OP_ADD;
    b.srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO;
    b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    b.alphaBlendOp = VK_BLEND_OP_ADD;
    return b;
}

void set_viewport(VkCommandBuffer cmd, VkExtent2D extent) {
    VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

}  // namespace brume::vk
