// A swapchain on the Device's surface (DeviceOptions::create_surface): format and present-mode
// choice, images and views, acquire and present, and recreation when the window changes size.
// A zero-sized (minimised) window has no swapchain: valid() is false until it has a size again.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace brume::vk {

class Swapchain {
public:
    // The surface's size when it has one, else `wanted` (a window's framebuffer size).
    Swapchain(const Device& device, VkExtent2D wanted);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Recreates the swapchain (after the device is idle); false when the surface is zero-sized.
    bool recreate(VkExtent2D wanted);
    // The next image, with `acquired` signalled when it may be written; nullopt when the swapchain
    // is out of date (recreate it and skip the frame) or there is none.
    std::optional<std::uint32_t> acquire(VkSemaphore acquired);
    // Queues image `index` for presentation once `ready` is signalled. False when the swapchain is
    // out of date or suboptimal: recreate it before the next frame.
    bool present(std::uint32_t index, VkSemaphore ready);

    bool valid() const { return swapchain_.get() != VK_NULL_HANDLE; }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }
    std::uint32_t image_count() const { return std::uint32_t(images_.size()); }
    VkImage image(std::uint32_t i) const { return images_[i]; }
    VkImageView view(std::uint32_t i) const { return views_[i]; }
    // Whether the images can be copied from (a capture of what the window shows).
    bool can_copy() const { return (usage_ & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0; }
    // Bumped by every recreation: what depends on the images (framebuffers) is made again.
    std::uint64_t generation() const { return generation_; }

private:
    const Device& device_;
    UniqueSwapchain swapchain_;
    std::vector<VkImage> images_;
    std::vector<UniqueImageView> views_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkImageUsageFlags usage_ = 0;
    VkColorSpaceKHR color_space_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    VkExtent2D extent_{};
    std::uint64_t generation_ = 0;
};

}  // namespace brume::vk
