#include "render/frame/swapchain_presenter.h"

namespace brume {

SwapchainPresenter::SwapchainPresenter(const vk::Device& device, VkExtent2D window_extent)
    : device_(device), swapchain_(device, window_extent), window_extent_(window_extent) {
    ensure_targets();
}

SwapchainPresenter::~SwapchainPresenter() { vkDeviceWaitIdle(device_.get()); }

void SwapchainPresenter::set_window_extent(VkExtent2D extent) {
    if (extent.width == window_extent_.width && extent.height == window_extent_.height) return;
    window_extent_ = extent;
    recreate_ = true;
}

void SwapchainPresenter::ensure_targets() {
    if (!swapchain_.valid()) return;
    if (!tone_map_ || tone_map_->format() != swapchain_.format())
        tone_map_ = std::make_unique<ToneMapPass>(device_, swapchain_.format(), VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    if (framebuffers_generation_ == swapchain_.generation()) return;
    framebuffers_.clear();
    for (std::uint32_t i = 0; i < swapchain_.image_count(); ++i)
        framebuffers_.push_back(tone_map_->make_framebuffer(swapchain_.view(i), swapchain_.extent()));
    framebuffers_generation_ = swapchain_.generation();
}

bool SwapchainPresenter::present(const FrameResources& frame, vk::FrameRing& ring) {
    if (recreate_ || !swapchain_.valid()) {
        framebuffers_.clear();
        swapchain_.recreate(window_extent_);
        recreate_ = false;
        ensure_targets();
    }
    if (!swapchain_.valid()) return false;  // minimised
    vk::FrameSlot& slot = ring.current();
    const std::optional<std::uint32_t> index = swapchain_.acquire(slot.image_acquired);
    if (!index) {
        recreate_ = true;
        return false;
    }
    tone_map_->record(slot.cmd, framebuffers_[*index], swapchain_.extent(), frame.hdr_view(), frame.extent(),
                      exposure_stops_, overlay_);
    ring.submit(slot.image_acquired, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, slot.ready_to_present);
    if (!swapchain_.present(*index, slot.ready_to_present)) recreate_ = true;
    return true;
}

}  // namespace brume
