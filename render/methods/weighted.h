// `wsum`, `wavg`, `wboit`: the unsorted blending methods (Maule, "Survey on Order Independent
// Transparency Techniques", section 5; McGuire & Bavoil 2013). One geometry pass of sphere impostors
// into accumulation targets (additive blending only, so the result cannot depend on draw order),
// then one full-screen pass that composites the accumulated layer over the opaque radiance:
//   wsum  weighted sum (Meshkin 2007), unclamped: it overshoots where the alphas add past 1;
//   wavg  weighted average (Bavoil & Myers 2008);
//   wboit weighted blended OIT, McGuire & Bavoil's eq. 9 depth weight with z in units of
//         D = z_max / 1.32 (weight_depth_scale).
// All three are exact for a pixel covered by one sphere. None takes a setting. The equations and
// the choices made here: docs/methods.md, wsum, wavg, wboit.
#pragma once

#include "render/image.h"
#include "render/frame/frame_resources.h"
#include "render/frame/gpu_method.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <memory>
#include <string>

namespace brume {

enum class WeightedMode : unsigned {
    Sum = 0,      // wsum
    Average = 1,  // wavg
    Blended = 2,  // wboit
};

class WeightedMethod : public GpuMethod {
public:
    WeightedMethod(vk::Device& device, WeightedMode mode);

    std::string name() const override;
    bool exact() const override { return false; }

    // The frame path's side (render/frame/gpu_method.h).
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

    // wboit's depth scale D (see above) for a scene.
    static double weight_depth_scale(const Scene& scene);

private:
    void ensure_targets(VkExtent2D extent);

    WeightedMode mode_;
    vk::UniquePipeline accumulate_pipeline_;
    vk::UniquePipeline composite_pipeline_;
    vk::Buffer params_;      // wboit's weight parameters (vec4: x = D)
    vk::DeviceImage accum_;  // rgba32f: sum(alpha c) and sum(alpha), weighted by w for wboit
    vk::DeviceImage extra_;  // r32f: N (wavg) or optical depth sum(tau * chord) (wsum, wboit)
};

// `--method wsum|wavg|wboit`: none takes a setting (std::invalid_argument if one is given).
std::unique_ptr<Method> make_wsum_method(vk::Device& device, const std::string& setting);
std::unique_ptr<Method> make_wavg_method(vk::Device& device, const std::string& setting);
std::unique_ptr<Method> make_wboit_method(vk::Device& device, const std::string& setting);

}  // namespace brume
