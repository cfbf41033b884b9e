#include "render/frame/swapchain_presenter.h"

#include <cstring>
#include <utility>

namespace brume {

SwapchainPresenter::SwapchainPresenter(const vk::Device& device, VkExtent2D window_extent)
    : device_(device), swapchain_(device, window_extent), window_extent_(window_extent) {
    ensure_targets();
}

SwapchainPresenter::~SwapchainPresenter() {
    const auto queue_lock = device_.lock_queue();
    vkDeviceWaitIdle(device_.get());
}

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
    return present_view(frame.hdr_view(), frame.extent(), ring);
}

bool SwapchainPresenter::present_deferred() {
    if (!deferred_index_) return false;
    if (!swapchain_.present(*deferred_index_, deferred_ready_)) recreate_ = true;
    deferred_index_.reset();
    return true;
}

bool SwapchainPresenter::present_view(VkImageView hdr, VkExtent2D hdr_extent, vk::FrameRing& ring) {
    present_deferred();  // the last image first (the caller waited for it: this does not block)
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
    tone_map_->record(slot.cmd, framebuffers_[*index], swapchain_.extent(), hdr, hdr_extent, exposure_stops_, overlay_);
    const bool capture = capture_requested_ && swapchain_.can_copy();
    const VkExtent2D extent = swapchain_.extent();
    if (capture) {
        const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * 4;
        if (capture_buffer_.size() != bytes)
            capture_buffer_ = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::Readback,
                                         "swapchain.capture");
        const VkImage image = swapchain_.image(*index);
        // The render pass left the image ready to present; the copy goes between it and the present.
        vk::image_barrier(slot.cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                          VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                          VK_ACCESS_2_TRANSFER_READ_BIT);
        vk::copy_image_to_host(slot.cmd, image, extent, capture_buffer_.get());
        vk::image_barrier(slot.cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                          VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, 0);
    }
    ring.submit(slot.image_acquired, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, slot.ready_to_present);
    if (deferred_ && !capture) {
        deferred_index_ = *index;
        deferred_ready_ = slot.ready_to_present;
        return true;
    }
    if (!swapchain_.present(*index, slot.ready_to_present)) recreate_ = true;
    if (capture) {
        // A capture is rare (a screenshot): waiting for this frame costs one frame of overlap.
        ring.wait();
        capture_.resize(std::size_t(extent.width) * extent.height * 4);
        std::memcpy(capture_.data(), capture_buffer_.mapped(), capture_.size());
        const VkFormat f = swapchain_.format();
        if (f == VK_FORMAT_B8G8R8A8_UNORM || f == VK_FORMAT_B8G8R8A8_SRGB)
            for (std::size_t p = 0; p < capture_.size(); p += 4) std::swap(capture_[p], capture_[p + 2]);
        capture_extent_ = extent;
        capture_requested_ = false;
    }
    return true;
}

bool SwapchainPresenter::capture_next_frame() {
    if (swapchain_.valid() && !swapchain_.can_copy()) return false;
    capture_requested_ = true;
    return true;
}

std::vector<std::uint8_t> SwapchainPresenter::take_capture(VkExtent2D& extent) {
    extent = capture_extent_;
    return std::exchange(capture_, {});
}

}  // namespace brume
