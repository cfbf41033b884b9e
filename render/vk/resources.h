// Buffers and images with their memory, one owner each. Host-visible buffers stay mapped.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstdint>
#include <string>
#include <vector>

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
    // A 2D image. With `array` (or layers > 1) view() is a 2D-array view of every layer, for shaders
    // that declare an array, and layer_view(i) a 2D view of layer i (for attachments).
    DeviceImage(const Device& device, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                const std::string& name, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT, std::uint32_t layers = 1,
                bool array = false);

    VkImage get() const { return image_; }
    VkImageView view() const { return view_; }  // every layer
    VkImageView layer_view(std::uint32_t layer) const { return layer_views_.empty() ? VkImageView(view_) : VkImageView(layer_views_[layer]); }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }
    std::uint32_t layers() const { return layers_; }
    VkDeviceSize bytes() const { return bytes_; }

private:
    UniqueImage image_;
    UniqueMemory memory_;
    UniqueImageView view_;
    std::vector<UniqueImageView> layer_views_;
    std::uint32_t layers_ = 1;
    VkDeviceSize bytes_ = 0;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent_{};
};

// Pipeline barriers (synchronization2), spelled out at each use so the ordering is visible there.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                   VkImageLayout new_layout, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access, std::uint32_t layers = 1);

// Copies a whole 2D colour image (in TRANSFER_SRC_OPTIMAL) into `buffer`, tightly packed, and makes
// the bytes visible to the host once the submission completes: a frame's readback.
void copy_image_to_host(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, VkBuffer buffer);

// Begins dynamic rendering into colour targets kept in GENERAL layout (they are also read as storage
// images), cleared to zero or loaded as they are.
void begin_color_rendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& views,
                           VkAttachmentLoadOp load);

std::string format_bytes(std::uint64_t bytes);

}  // namespace brume::vk
