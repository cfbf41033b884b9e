#include "render/frame/offscreen_presenter.h"

#include <cstring>

namespace brume {

using namespace vk;

OffscreenPresenter::OffscreenPresenter(const Device& device, VkExtent2D extent, double exposure_stops)
    : extent_(extent),
      exposure_stops_(exposure_stops),
      tone_map_(device, kFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL),
      target_(device, kFormat, extent, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
              VK_IMAGE_ASPECT_COLOR_BIT, "offscreen.target"),
      framebuffer_(tone_map_.make_framebuffer(target_.view(), extent)),
      readback_(device, VkDeviceSize(extent.width) * extent.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                MemoryUse::Readback, "offscreen.readback") {}

bool OffscreenPresenter::present(const FrameResources& frame, FrameRing& ring) {
    VkCommandBuffer cmd = ring.current().cmd;
    tone_map_.record(cmd, framebuffer_, extent_, frame.hdr_view(), frame.extent(), exposure_stops_);
    copy_image_to_host(cmd, target_.get(), extent_, readback_.get());
    ring.submit();
    ring.wait();
    pixels_.resize(std::size_t(extent_.width) * extent_.height * 4);
    std::memcpy(pixels_.data(), readback_.mapped(), pixels_.size());
    return true;
}

}  // namespace brume
