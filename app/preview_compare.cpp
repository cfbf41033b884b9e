#include "app/preview_compare.h"

#include "render/frame/frame_resources.h"

#include <cmath>
#include <stdexcept>

namespace brume::app {

Image compose_comparison(const Image& method, const Image& other, CompareMode mode) {
    if (method.width != other.width || method.height != other.height)
        throw std::invalid_argument("compose_comparison: the two frames differ in size");
    Image out(method.width, method.height);
    const int split = method.width / 2;
    for (int j = 0; j < method.height; ++j)
        for (int i = 0; i < method.width; ++i) {
            const float* a = method.pixel(i, j);
            const float* b = other.pixel(i, j);
            float* o = out.pixel(i, j);
            for (int c = 0; c < 3; ++c) {
                if (mode == CompareMode::Difference)
                    o[c] = std::abs(a[c] - b[c]) * kDifferenceGain;
                else
                    o[c] = i < split ? a[c] : i == split ? 1.0f : b[c];
            }
        }
    return out;
}

ComparisonPresenter::ComparisonPresenter(const vk::Device& device) : device_(device), ring_(device, 1) {}

ComparisonPresenter::~ComparisonPresenter() { ring_.wait_all(); }

bool ComparisonPresenter::present(SwapchainPresenter& presenter, const Image& composite) {
    const VkExtent2D extent{std::uint32_t(composite.width), std::uint32_t(composite.height)};
    // One image for every frame: the last frame's tone map must be done reading it before it is written.
    ring_.wait_all();
    if (extent.width != extent_.width || extent.height != extent_.height) {
        device_.wait_idle();  // the tone-map pass may still hold the old image's view
        image_ = vk::DeviceImage(device_, FrameResources::kHdrFormat, extent,
                                 VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT,
                                 "preview.comparison");
        staging_ = vk::Buffer(device_, VkDeviceSize(extent.width) * extent.height * 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                              vk::MemoryUse::Upload, "preview.comparison.staging");
        extent_ = extent;
    }
    float* texels = staging_.as<float>();
    for (std::size_t p = 0, n = std::size_t(extent.width) * extent.height; p < n; ++p) {
        for (int c = 0; c < 3; ++c) texels[p * 4 + c] = composite.rgb[p * 3 + c];
        texels[p * 4 + 3] = 1.0f;
    }
    VkCommandBuffer cmd = ring_.begin_next().cmd;
    vk::image_barrier(cmd, image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COPY_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    vkCmdCopyBufferToImage(cmd, staging_.get(), image_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    vk::image_barrier(cmd, image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                      VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    // When nothing is shown (a minimised or out-of-date window) nothing is submitted: the next
    // begin_next() resets the recorded upload.
    return presenter.present_view(image_.view(), extent, ring_);
}

}  // namespace brume::app
