// A presenter without a window: tone-maps the frame into an 8-bit RGBA image and reads it back, as
// a window would show it. Tests prove with it that the window shows what the PNG writer writes;
// a preview can take screenshots with it.
#pragma once

#include "render/frame/presenter.h"
#include "render/frame/tone_map.h"
#include "render/vk/resources.h"

#include <cstdint>
#include <vector>

namespace brume {

class OffscreenPresenter : public Presenter {
public:
    static constexpr VkFormat kFormat = VK_FORMAT_R8G8B8A8_UNORM;

    OffscreenPresenter(const vk::Device& device, VkExtent2D extent, double exposure_stops = 0.0);
    // Submits the tone-map pass and waits for it; pixels() then holds the frame.
    bool present(const FrameResources& frame, vk::FrameRing& ring) override;
    // Row-major RGBA, 8 bits a channel, top row first.
    const std::vector<std::uint8_t>& pixels() const { return pixels_; }
    VkExtent2D extent() const { return extent_; }

private:
    VkExtent2D extent_;
    double exposure_stops_;
    ToneMapPass tone_map_;
    vk::DeviceImage target_;
    vk::UniqueFramebuffer framebuffer_;
    vk::Buffer readback_;
    std::vector<std::uint8_t> pixels_;
};

}  // namespace brume
