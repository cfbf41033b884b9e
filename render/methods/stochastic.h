// `stochastic` (seed 001 section 6.1, Enderton et al. 2010): stochastic transparency with S samples
// per pixel. Every sphere fragment covers each sample of its pixel with probability alpha and writes
// its colour there, depth tested so the nearest covering sphere wins; averaging the samples estimates
// sum_i alpha_i c_i prod_(j nearer) (1 - alpha_j) + C_bg prod_i (1 - alpha_i), the "over" composite,
// without sorting. Order is by the sphere's clipped entry distance (nearest wins; depth
// 1 / (1 + t_entry) in D32, so spheres containing the eye, all at distance 0, tie and the first
// drawn wins).
//
// Samples: lavapipe offers 1 and 4 samples per pixel, so S (a power of two, 1..64) is rendered as
// S/4 geometry passes into a 4x MSAA target (S = 1, 2: S single-sample passes). Each pass's samples
// are averaged by the MSAA resolve into one layer of an array image, and the final pass averages the
// layers. Every sample lies on the pixel-centre ray (the fragment shader runs once per pixel, at its
// centre); the MSAA samples serve only as S independent depth-tested slots.
//
// Coverage (stratified, as in the seed): for sphere i at pixel p a hash of (p, i) gives xi in [0, 1)
// and an odd multiplier a and offset b; sample g (0..S-1) is covered when
// ((a g + b) mod S + xi) / S < alpha_i. So the sphere covers floor(alpha S + xi') of the S samples
// (xi' uniform), each sample with probability exactly alpha, independently of every other sphere.
// The hash has no frame input: the noise is the same in every frame for the same sphere id.
//
// Resolve, with A = fraction of samples covered by any sphere and C_s = average colour of covered
// samples:
//   plain     (setting "S,plain"):   C = A C_s + (1 - A) C_bg                 (the plain average)
//   corrected (default, "S"):        C = alpha_total C_s + (1 - alpha_total) C_bg,
//       alpha_total = 1 - prod(1 - alpha_i) from an extra accumulation pass (the seed's alpha
//       correction, eq. 6.1: the average colour times alpha_total / (R/S)), computed as
//       1 - exp(-sum tau_i chord_i). Where no sample is covered (R = 0), C_s falls back to the
//       alpha-weighted average sum(alpha_i c_i) / sum(alpha_i) from the same pass.
//   The corrected form is exact for a pixel covered by one sphere, at any S.
//
// Depth-based variant (setting "S,depth"; Enderton et al. 2010 section 3.3, seed steps 1-5):
//   1. S single-sample depth passes (per-sample depth of a multisampled image cannot be read
//      without a feature Brume does not enable): pass k draws sample k of the same stratified
//      coverage as above and writes the covering sphere's entry distance t0 into layer k of an R32F
//      array (nearest wins through the same D32 test; cleared to 3e38 where nothing covers).
//   2. One accumulation pass over every sphere fragment: vis = count_k(z_k >= t0) / S (equality,
//      to a relative 1e-5 since t0 is recomputed, counts as not in front: no self-occlusion);
//      additively sum(alpha vis c), sum(alpha vis) and the optical depth sum(tau chord).
//   3. Resolve: C = alpha_total sum(alpha vis c) / sum(alpha vis) + (1 - alpha_total) C_bg with
//      alpha_total = 1 - exp(-sum tau chord). vis estimates prod_(j in front)(1 - alpha_j) without
//      bias; the normalisation makes one sphere exact at any S (its vis is always 1).
// The scene's min_transmittance cut-off plays no part.
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
