#include "render/vk/resources.h"

#include "render/vk/vk_check.h"

#include <cstdio>

namespace brume::vk {
namespace {

UniqueMemory allocate(const Device& device, const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                      VkMemoryPropertyFlags preferred, const std::string& name) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = req.size;
    info.memoryTypeIndex = device.find_memory_type(req.memoryTypeBits, required, preferred);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkResult r = vkAllocateMemory(device.get(), &info, nullptr, &memory);
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw VulkanError(r, "out of memory allocating " + format_bytes(req.size) + " for '" + name + "' on " +
                                 device.name() + " (" + result_name(r) + ")");
    VK_CHECK(r);
    device.set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, memory, name.c_str());
    return UniqueMemory(device.get(), memory);
}

}  // namespace

std::string format_bytes(std::uint64_t bytes) {
    char text[64];
    if (bytes >= (1ull << 30)) std::snprintf(text, sizeof text, "%.2f GiB (%llu bytes)", bytes / double(1ull << 30), (unsigned long long)bytes);
    else if (bytes >= (1ull << 20)) std::snprintf(text, sizeof text, "%.1f MiB (%llu bytes)", bytes / double(1ull << 20), (unsigned long long)bytes);
    else std::snprintf(text, sizeof text, "%llu bytes", (unsigned long long)bytes);
    return text;
}

Buffer::Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use,
               const std::string& name)
    : size_(size) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buffer;
    VK_CHECK(vkCreateBuffer(device.get(), &info, nullptr, &buffer));
    buffer_ = UniqueBuffer(device.get(), buffer);
    device.set_name(VK_OBJECT_TYPE_BUFFER, buffer, name.c_str());

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.get(), buffer, &req);
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    switch (use) {
    case MemoryUse::Device: memory_ = allocate(device, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, name); break;
    case MemoryUse::Upload: memory_ = allocate(device, req, host, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, name); break;
    case MemoryUse::Readback: memory_ = allocate(device, req, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT, name); break;
    }
    VK_CHECK(vkBindBufferMemory(device.get(), buffer, memory_, 0));
    if (use != MemoryUse::Device) VK_CHECK(vkMapMemory(device.get(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

DeviceImage::DeviceImage(const Device& device, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage,
                         VkImageAspectFlags aspect, const std::string& name, VkSampleCountFlagBits samples,
                         std::uint32_t layers, bool array)
    : layers_(layers), format_(format), extent_(extent) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = 1;
    info.arrayLayers = layers;
    info.samples = samples;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImage image;
    VK_CHECK(vkCreateImage(device.get(), &info, nullptr, &image));
    image_ = UniqueImage(device.get(), image);
    device.set_name(VK_OBJECT_TYPE_IMAGE, image, name.c_str());

    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.get(), image, &req);
    memory_ = allocate(device, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, name);
    VK_CHECK(vkBindImageMemory(device.get(), image, memory_, 0));
    bytes_ = req.size;

    auto make_view = [&](VkImageViewType type, std::uint32_t first, std::uint32_t count, const std::string& view_name) {
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = image;
        view.viewType = type;
        view.format = format;
        view.subresourceRange = {aspect, 0, 1, first, count};
        VkImageView v;
        VK_CHECK(vkCreateImageView(device.get(), &view, nullptr, &v));
        device.set_name(VK_OBJECT_TYPE_IMAGE_VIEW, v, view_name.c_str());
        return UniqueImageView(device.get(), v);
    };
    array = array || layers > 1;
    view_ = make_view(array ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D, 0, layers, name + ".view");
    if (array)
        for (std::uint32_t l = 0; l < layers; ++l)
            layer_views_.push_back(make_view(VK_IMAGE_VIEW_TYPE_2D, l, 1, name + ".layer" + std::to_string(l)));
}

void copy_image_to_host(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, VkBuffer buffer) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &region);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
}

void begin_color_rendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& views,
                           VkAttachmentLoadOp load) {
    std::vector<VkRenderingAttachmentInfo> targets(views.size(), {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO});
    for (std::size_t k = 0; k < views.size(); ++k) {
        targets[k].imageView = views[k];
        targets[k].imageLayout = VK_IMAGE_LAYOUT_GENERAL;
        targets[k].loadOp = load;
        targets[k].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        targets[k].clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    }
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = std::uint32_t(targets.size());
    info.pColorAttachments = targets.data();
    vkCmdBeginRendering(cmd, &info);
}

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = src_stage;
    barrier.srcAccessMask = src_access;
    barrier.dstStageMask = dst_stage;
    barrier.dstAccessMask = dst_access;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                   VkImageLayout new_layout, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access, std::uint32_t layers) {
    VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    barrier.srcStageMask = src_stage;
    barrier.srcAccessMask = src_access;
    barrier.dstStageMask = dst_stage;
    barrier.dstAccessMask = dst_access;
    barrier.oldLayout = old_layout;
    barrier.newLayout = new_layout;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {aspect, 0, 1, 0, layers};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace brume::vk
