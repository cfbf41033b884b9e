// Two methods side by side: the left half of the view shows the method, the right half another one
// (ppll beside sorted, to watch popping), split by a one-pixel white line; or the difference view,
// |method - other| per channel times 8 (3 stops), which shows where and how much they disagree.
// Both frames are read back through the frame path and composed on the CPU; the composite is uploaded
// and presented through the same tone-map pass (SwapchainPresenter::present_view). It costs two frames
// and a readback each, which a comparison can afford.
#pragma once

#include "render/frame/swapchain_presenter.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/frame_ring.h"
#include "render/vk/resources.h"

namespace brume::app {

enum class CompareMode { Off, Split, Difference };

inline constexpr float kDifferenceGain = 8.0f;

// The composite of `method` (left, or the minuend) and `other` (same size). Split: columns left of
// width / 2 are `method`'s, the column at width / 2 is white (radiance 1), the rest `other`'s.
Image compose_comparison(const Image& method, const Image& other, CompareMode mode);

class ComparisonPresenter {
public:
    explicit ComparisonPresenter(const vk::Device& device);
    // Waits for the last frame that samples the composite: its image and staging buffer go with it.
    ~ComparisonPresenter();
    // Uploads `composite` and presents it; as SwapchainPresenter::present.
    bool present(SwapchainPresenter& presenter, const Image& composite);

private:
    const vk::Device& device_;
    vk::FrameRing ring_;
    vk::DeviceImage image_;
    vk::Buffer staging_;
    VkExtent2D extent_{};
};

}  // namespace brume::app
