// The one descriptor set layout every Brume pass uses (bindings in shaders/shared.h), its pipeline
// layout, and a set to write into. Passes differ only in which bindings their shaders touch.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <vector>

namespace brume::vk {

class SharedDescriptors {
public:
    explicit SharedDescriptors(const Device& device);

    VkDescriptorSetLayout set_layout() const { return set_layout_; }
    VkPipelineLayout pipeline_layout() const { return pipeline_layout_; }
    VkDescriptorSet set() const { return set_; }
    void bind(VkCommandBuffer cmd, VkPipelineBindPoint point = VK_PIPELINE_BIND_POINT_GRAPHICS) const;

    void write_uniform(std::uint32_t binding, VkBuffer buffer) const;
    void write_storage(std::uint32_t binding, VkBuffer buffer) const;
    void write_storage_array(std::uint32_t binding, const std::vector<VkBuffer>& buffers) const;
    void write_storage_image(std::uint32_t binding, VkImageView view) const;

private:
    const Device& device_;
    UniqueDescriptorSetLayout set_layout_;
    UniquePipelineLayout pipeline_layout_;
    UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace brume::vk
