// The unsorted blending methods of seed 001 section 5 and McGuire & Bavoil 2013: one geometry pass of
// sphere impostors into accumulation targets (additive blending only, so the result cannot depend on
// draw order), then one full-screen pass that composites the accumulated layer over the opaque
// radiance. Each sphere is one fragment per pixel with sphere_sample.glsl's alpha_i and colour c_i;
// C_bg is the opaque pass's radiance behind the pixel.
//
//   wsum  (Meshkin 2007, seed eq. 5.1):  C = sum(alpha_i c_i) + C_bg (1 - sum alpha_i)
//   wavg  (Bavoil & Myers 2008, eqs. 5.2-5.4), with N the pixel's fragment count:
//         C_avg = sum(alpha_i c_i) / sum(alpha_i),  alpha_avg = sum(alpha_i) / N,
//         C = C_avg (1 - (1 - alpha_avg)^N) + C_bg (1 - alpha_avg)^N
//   wboit (McGuire & Bavoil 2013, their eq. 9 weight):
//         w_i = alpha_i * clamp(0.03 / (1e-5 + (z_i / D)^4), 1e-2, 3e3),
//         C = [sum(w_i alpha_i c_i) / sum(w_i alpha_i)] (1 - R) + C_bg R,  R = prod(1 - alpha_i)
//
// Choices made here:
// - z_i is the distance along the pixel ray to the sphere's clipped entry point.
// - D adapts the paper's z/200 (scenes of 0.1-500 units) to Brume's scene units: D = z_max / 1.32,
//   with z_max the farthest point of any sphere from the eye, so the back of the scene lands where the
//   paper's weight reaches its lower clamp (z = 264 there) and w ~ z^-4 spans the whole scene. Scaling D
//   scales every unclamped weight alike, which the normalisation cancels.
// - R is accumulated as the optical depth sum(tau_i * chord_i) (additive) and taken as exp(-sum): the
//   same product, but exact for thin spheres, where 1 - alpha rounds to 1 in float.
// - (1 - alpha_avg)^N is evaluated as exp(N log(1 - alpha_avg)) with a series for small alpha_avg.
// - wsum keeps the seed's equation unclamped: where sum(alpha_i) > 1 the background weight is
//   negative. That is the method's failure mode, not hidden.
// - The scene's min_transmittance cut-off plays no part (none of the equations has a transmittance
//   per layer).
// All three equal the exact answer alpha c + (1 - alpha) C_bg for a pixel covered by one sphere.
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
