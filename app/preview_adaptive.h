// The preview's internal resolution: while playing (or while the camera moves) a frame slower than
// the target frame rate is rendered at a smaller size, scaled up by the tone-map pass; when the view
// stands still it refines back to the full viewport. Changes are damped (a new scale at most every
// half second, in steps of 1/16) because every change recreates the frame's targets.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

namespace brume::app {

class AdaptiveResolution {
public:
    explicit AdaptiveResolution(double target_fps = 30.0) : target_fps_(target_fps) {}

    // After each shown frame: the wall-clock seconds it took, and whether the view is moving.
    void frame_done(double seconds, bool moving);
    void set_enabled(bool enabled);
    bool enabled() const { return enabled_; }
    double target_fps() const { return target_fps_; }
    void set_target_fps(double fps) { target_fps_ = fps > 1.0 ? fps : 1.0; }
    double scale() const { return scale_; }
    // The size to render at for a viewport of `viewport` pixels (at least 16x16 when not zero).
    VkExtent2D internal_extent(VkExtent2D viewport) const;

    static constexpr double kMinScale = 0.25;

private:
    double target_fps_;
    bool enabled_ = true;
    double scale_ = 1.0;
    double smoothed_seconds_ = 0.0;
    double since_change_ = 0.0;
};

}  // namespace brume::app
