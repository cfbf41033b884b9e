#include "render/vk/swapchain.h"

#include "render/vk/vk_check.h"

#include <algorithm>
#include <string>

namespace brume::vk {
namespace {

// UNORM first: the tone-map pass encodes sRGB exactly as the PNG writer does. An sRGB format is
// taken when it is all there is (the hardware encodes then).
VkSurfaceFormatKHR choose_format(const std::vector<VkSurfaceFormatKHR>& formats) {
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                            VK_FORMAT_R8G8B8A8_SRGB})
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    return formats.front();
}

}  // namespace

Swapchain::Swapchain(const Device& device, VkExtent2D wanted) : device_(device) {
    if (!device.surface()) throw VulkanError(VK_ERROR_INITIALIZATION_FAILED, "a swapchain needs a Device made with a surface");
    recreate(wanted);
}

Swapchain::~Swapchain() {
    if (!swapchain_.get()) return;
    const auto queue_lock = device_.lock_queue();
    vkDeviceWaitIdle(device_.get());
}

bool Swapchain::recreate(VkExtent2D wanted) {
    VkPhysicalDevice physical = device_.physical();
    VkSurfaceKHR surface = device_.surface();
    VkSurfaceCapabilitiesKHR caps;
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &caps));
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == 0xFFFFFFFFu) {  // the surface leaves the size to the swapchain
        extent.width = std::clamp(wanted.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(wanted.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    device_.wait_idle();
    views_.clear();
    images_.clear();
    if (extent.width == 0 || extent.height == 0 || wanted.width == 0 || wanted.height == 0) {
        swapchain_.reset();  // minimised: nothing to present to
        extent_ = {0, 0};
        ++generation_;
        return false;
    }

    std::uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(count);
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data()));
    if (formats.empty()) throw VulkanError(VK_ERROR_FORMAT_NOT_SUPPORTED, "the window's surface offers no image format");
    const VkSurfaceFormatKHR format = choose_format(formats);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface;
    info.minImageCount = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;
    info.imageFormat = format.format;
    info.imageColorSpace = format.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                      (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);  // screenshots, where allowed
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                            ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                            : caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always there; paces the preview to the display
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_.get();
    VkSwapchainKHR swapchain;
    VK_CHECK(vkCreateSwapchainKHR(device_.get(), &info, nullptr, &swapchain));
    swapchain_ = UniqueSwapchain(device_.get(), swapchain);  // destroys the old one
    device_.set_name(VK_OBJECT_TYPE_SWAPCHAIN_KHR, swapchain, "swapchain");

    VK_CHECK(vkGetSwapchainImagesKHR(device_.get(), swapchain, &count, nullptr));
    images_.resize(count);
    VK_CHECK(vkGetSwapchainImagesKHR(device_.get(), swapchain, &count, images_.data()));
    for (std::uint32_t i = 0; i < count; ++i) {
        VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view_info.image = images_[i];
        view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view_info.format = format.format;
        view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view;
        VK_CHECK(vkCreateImageView(device_.get(), &view_info, nullptr, &view));
        views_.emplace_back(device_.get(), view);
        device_.set_name(VK_OBJECT_TYPE_IMAGE_VIEW, view, ("swapchain.view[" + std::to_string(i) + "]").c_str());
    }
    format_ = format.format;
    usage_ = info.imageUsage;
    color_space_ = format.colorSpace;
    extent_ = extent;
    ++generation_;
    return true;
}

std::optional<std::uint32_t> Swapchain::acquire(VkSemaphore acquired) {
    if (!valid()) return std::nullopt;
    std::uint32_t index = 0;
    const VkResult r = vkAcquireNextImageKHR(device_.get(), swapchain_, UINT64_MAX, acquired, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
    if (r != VK_SUBOPTIMAL_KHR) VK_CHECK(r);  // suboptimal still signals `acquired`: use the image
    return index;
}

bool Swapchain::present(std::uint32_t index, VkSemaphore ready) {
    VkSwapchainKHR swapchain = swapchain_;
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &ready;
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain;
    info.pImageIndices = &index;
    VkResult r;
    {
        const auto queue_lock = device_.lock_queue();
        r = vkQueuePresentKHR(device_.queue(), &info);
    }
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
    VK_CHECK(r);
    return true;
}

}  // namespace brume::vk
