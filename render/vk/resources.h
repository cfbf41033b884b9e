// Buffers and images with their memory, one owner each. Host-visible buffers stay mapped.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstdint>
#include <string>

namespace brume::vk {

enum class MemoryUse {
    Device,    // GPU only
    Upload,    // written by the CPU every frame, read by the GPU (device-local if the device allows)
    Readback,  // written by the GPU, read by the CPU
};

class Buffer {
public:
    Buffer() = default;
    Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use, const std::string& name);

    VkBuffer get() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }
    template <typename T>
    T* as() const { return static_cast<T*>(mapped_); }

private:
    UniqueBuffer buffer_;
    UniqueMemory memory_;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

class DeviceImage {
public:
    DeviceImage() = default;
    DeviceImage(const Device& device, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage, VkImageAspectFlags aspect,
          const std::string& name);

    VkImage get() const { return image_; }
    VkImageView view() const { return view_; }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }

private:
    UniqueImage image_;
    UniqueMemory memory_;
    UniqueImageView view_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent_{};
};

// Pipeline barriers (synchronization2), spelled out at each use so the ordering is visible there.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                   VkImageLayout new_layout, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

std::string format_bytes(std::uint64_t bytes);

}  // namespace brume::vk
