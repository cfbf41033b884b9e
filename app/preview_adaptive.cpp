#include "app/preview_adaptive.h"

#include <algorithm>
#include <cstdint>
#include <cmath>

namespace brume::app {

void AdaptiveResolution::set_enabled(bool enabled) {
    enabled_ = enabled;
    if (!enabled_) scale_ = 1.0;
}

void AdaptiveResolution::frame_done(double seconds, bool moving) {
    smoothed_seconds_ = smoothed_seconds_ == 0.0 ? seconds : 0.8 * smoothed_seconds_ + 0.2 * seconds;
    since_change_ += seconds;
    if (!enabled_) return;
    if (!moving) {
        scale_ = 1.0;  // a still view refines to full resolution
        return;
    }
    if (since_change_ < 0.5) return;
    // Frame time grows about with the pixel count, so the side scales with the square root.
    const double budget = 1.0 / target_fps_;
    double wanted = scale_ * std::sqrt(budget / std::max(smoothed_seconds_, 1e-6));
    if (wanted > scale_ && smoothed_seconds_ > 0.7 * budget) wanted = scale_;  // close enough: stay
    wanted = std::clamp(std::round(wanted * 16.0) / 16.0, kMinScale, 1.0);
    if (wanted != scale_) {
        scale_ = wanted;
        since_change_ = 0.0;
        smoothed_seconds_ = 0.0;
    }
}

VkExtent2D AdaptiveResolution::internal_extent(VkExtent2D viewport) const {
    if (viewport.width == 0 || viewport.height == 0) return viewport;
    auto side = [&](std::uint32_t v) { return std::max<std::uint32_t>(16, std::uint32_t(std::lround(v * scale_))); };
    return {std::min(viewport.width, side(viewport.width)), std::min(viewport.height, side(viewport.height))};
}

}  // namespace brume::app
