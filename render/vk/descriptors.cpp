#include "render/vk/descriptors.h"

#include "render/vk/vk_check.h"
#include "shaders/shared.h"

#include <stdexcept>

namespace brume::vk {

SharedDescriptors::SharedDescriptors(const Device& device) : device_(device) {
    using namespace gpu;
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_COMPUTE_BIT;
    std::vector<VkDescriptorSetLayoutBinding> bindings = {
        {BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages, nullptr},
        {BINDING_SPHERES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr},
        {BINDING_BOXES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr},
        {BINDING_OPAQUE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, stages, nullptr},
        {BINDING_HEADS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr},
        {BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr},
        {BINDING_POOL, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, MAX_POOL_PARTS, stages, nullptr},
    };
    for (uint i = 0; i < METHOD_BUFFERS; ++i)
        bindings.push_back({BINDING_METHOD_BUFFER_FIRST + i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    for (uint i = 0; i < METHOD_IMAGES; ++i)
        bindings.push_back({BINDING_METHOD_IMAGE_FIRST + i, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, stages, nullptr});
    bindings.push_back({BINDING_SUN_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    if (bindings.size() != BINDING_COUNT) throw std::logic_error("descriptor bindings out of step with shared.h");
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = std::uint32_t(bindings.size());
    layout_info.pBindings = bindings.data();
    VkDescriptorSetLayout set_layout;
    VK_CHECK(vkCreateDescriptorSetLayout(device.get(), &layout_info, nullptr, &set_layout));
    set_layout_ = UniqueDescriptorSetLayout(device.get(), set_layout);
    device.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, set_layout, "brume.set_layout");

    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &set_layout;
    VkPipelineLayout pipeline_layout;
    VK_CHECK(vkCreatePipelineLayout(device.get(), &pl, nullptr, &pipeline_layout));
    pipeline_layout_ = UniquePipelineLayout(device.get(), pipeline_layout);
    device.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, pipeline_layout, "brume.pipeline_layout");

    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 5 + MAX_POOL_PARTS + METHOD_BUFFERS},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1 + METHOD_IMAGES}};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 3;
    pool_info.pPoolSizes = sizes;
    VkDescriptorPool pool;
    VK_CHECK(vkCreateDescriptorPool(device.get(), &pool_info, nullptr, &pool));
    pool_ = UniqueDescriptorPool(device.get(), pool);

    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    VK_CHECK(vkAllocateDescriptorSets(device.get(), &alloc, &set_));
    device.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET, set_, "brume.set");
}

void SharedDescriptors::bind(VkCommandBuffer cmd, VkPipelineBindPoint point) const {
    vkCmdBindDescriptorSets(cmd, point, pipeline_layout_, 0, 1, &set_, 0, nullptr);
}

void SharedDescriptors::write_uniform(std::uint32_t binding, VkBuffer buffer) const {
    VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set_;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(device_.get(), 1, &w, 0, nullptr);
}

void SharedDescriptors::write_storage(std::uint32_t binding, VkBuffer buffer) const {
    write_storage_array(binding, {buffer});
}

void SharedDescriptors::write_storage_array(std::uint32_t binding, const std::vector<VkBuffer>& buffers) const {
    std::vector<VkDescriptorBufferInfo> infos;
    for (VkBuffer b : buffers) infos.push_back({b, 0, VK_WHOLE_SIZE});
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set_;
    w.dstBinding = binding;
    w.descriptorCount = std::uint32_t(infos.size());
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = infos.data();
    vkUpdateDescriptorSets(device_.get(), 1, &w, 0, nullptr);
}

void SharedDescriptors::write_storage_image(std::uint32_t binding, VkImageView view) const {
    VkDescriptorImageInfo info{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set_;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    w.pImageInfo = &info;
    vkUpdateDescriptorSets(device_.get(), 1, &w, 0, nullptr);
}

}  // namespace brume::vk
