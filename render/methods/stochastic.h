// `stochastic` (stochastic transparency; Maule, "Survey on Order Independent Transparency
// Techniques", section 6.1, and Enderton et al. 2010): each sphere fragment covers each of S samples
// per pixel with probability alpha (stratified, from a hash of pixel and sphere with no frame input,
// so the noise is the same in every frame), the nearest covering sphere wins each sample's depth
// test, and averaging the samples estimates the "over" composite without sorting.
// Settings: "S" (a power of two, 1..64, default 8) with the alpha correction; "S,plain" the plain
// average; "S,depth" depth-based visibility, also alpha-corrected. The corrected and depth forms are
// exact for a pixel covered by one sphere at any S; all converge as S grows. S/4 passes of 4x MSAA
// (S = 1, 2: S single-sample passes). The scene's min_transmittance plays no part.
// Coverage, the resolve equations and the depth-based passes: docs/methods.md, stochastic.
#pragma once

#include "render/image.h"
#include "render/frame/frame_resources.h"
#include "render/frame/gpu_method.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace brume {

struct StochasticOptions {
    std::uint32_t samples = 8;  // S: a power of two, 1..64
    bool alpha_correction = true;  // false: ",plain"
    bool depth_based = false;      // ",depth" (always alpha-corrected)
};

// Parses "S", "S,plain" or "S,depth" (empty: the defaults). Throws std::invalid_argument naming the problem.
StochasticOptions parse_stochastic_setting(const std::string& setting);

class StochasticMethod : public GpuMethod {
public:
    StochasticMethod(vk::Device& device, StochasticOptions options = {});
    ~StochasticMethod() override;

    std::string name() const override;
    bool exact() const override { return false; }

    // The frame path's side (render/frame/gpu_method.h).
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

    std::uint32_t samples() const { return options_.samples; }
    std::uint32_t passes() const { return passes_; }

private:
    struct Targets;
    void ensure_targets(VkExtent2D extent);
    void record_accumulation(VkCommandBuffer cmd, const FrameContext& ctx, VkPipeline pipeline);
    void record_coverage(VkCommandBuffer cmd, const FrameContext& ctx);

    StochasticOptions options_;
    std::uint32_t pass_samples_;  // 4 (MSAA) or 1
    std::uint32_t passes_;
    vk::UniquePipeline alpha_pipeline_;
    vk::UniquePipeline cover_pipeline_;
    vk::UniquePipeline resolve_pipeline_;
    vk::UniquePipeline depth_accum_pipeline_;  // ",depth" only
    std::unique_ptr<Targets> targets_;
};

// `--method stochastic[:S[,plain|,depth]]`, S default 8.
std::unique_ptr<Method> make_stochastic_method(vk::Device& device, const std::string& setting);

}  // namespace brume
