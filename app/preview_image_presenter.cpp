#include "app/preview_image_presenter.h"

#include "render/frame/frame_resources.h"

#include <utility>

namespace brume::app {

ImagePresenter::ImagePresenter(const vk::Device& device) : device_(device), ring_(device, 1) {}

ImagePresenter::~ImagePresenter() {
    // The ring's fences cover its submissions, not the queue present that waits on a slot's
    // ready_to_present semaphore: only an idle device says that the semaphores are free to go.
    const auto queue_lock = device_.lock_queue();
    vkDeviceWaitIdle(device_.get());
}

void ImagePresenter::set_image(Image image) { pending_ = std::move(image); }

bool ImagePresenter::present(SwapchainPresenter& presenter) {
    // One image and one staging buffer: the last present must be done reading them before they are
    // written (the main loop calls this once ready(), so this does not wait).
    ring_.wait_all();
    if (pending_.width != 0) {
        const VkExtent2D extent{std::uint32_t(pending_.width), std::uint32_t(pending_.height)};
        if (extent.width != extent_.width || extent.height != extent_.height) {
            // No submission of this ring is in flight (above), and only this ring's presents sample
            // the image: it may go. The new one is made before the old one is destroyed, so its view
            // is a new handle and the tone-map pass writes it into its descriptor set.
            image_ = vk::DeviceImage(device_, FrameResources::kHdrFormat, extent,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                     VK_IMAGE_ASPECT_COLOR_BIT, "preview.shown_frame");
            staging_ = vk::Buffer(device_, VkDeviceSize(extent.width) * extent.height * 16,
                                  VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::Upload, "preview.shown_frame.staging");
            extent_ = extent;
        }
        float* texels = staging_.as<float>();
        for (std::size_t p = 0, n = std::size_t(extent.width) * extent.height; p < n; ++p) {
            for (int c = 0; c < 3; ++c) texels[p * 4 + c] = pending_.rgb[p * 3 + c];
            texels[p * 4 + 3] = 1.0f;
        }
        pending_ = {};
        upload_ = true;
    }
    if (extent_.width == 0) return false;  // nothing rendered yet
    VkCommandBuffer cmd = ring_.begin_next().cmd;
    if (upload_) {
        vk::image_barrier(cmd, image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0,
                          VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent_.width, extent_.height, 1};
        vkCmdCopyBufferToImage(cmd, staging_.get(), image_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        vk::image_barrier(cmd, image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                          VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                          VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
    // When nothing is shown (a minimised or out-of-date window) nothing is submitted: the copy is
    // recorded again with the next present, and the next begin_next() resets this one.
    const bool shown = presenter.present_view(image_.view(), extent_, ring_);
    if (shown) upload_ = false;
    return shown;
}

}  // namespace brume::app
