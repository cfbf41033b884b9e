// `auto`: model no more than the frame needs. When no two spheres on screen share volume,
// compositing whole spheres back to front in power-distance order (|c - eye|^2 - r^2) is exact, with
// each sphere's chord clipped by the eye and the opaque surface, and needs no per-pixel lists; only
// frames with intersecting spheres pay for ppll. The choice is made per frame on the CPU
// (sim/sphere_overlap.h, O(n log n); why: docs/decisions.md, "`auto` decides per frame on the CPU").
//
// One difference remains: the compositor integrates every sphere, while ppll and the reference stop
// once transmittance falls below the scene's min_transmittance. What lies behind such a point
// contributes at most min_transmittance times its radiance, so auto is exact wherever the scene
// sets min_transmittance = 0 and within that bound otherwise.
#pragma once

#include "render/methods/method.h"
#include "render/methods/ppll.h"
#include "render/methods/sorted.h"

namespace brume {

class AutoMethod : public GpuMethod {
public:
    // `ppll` configures the lists for the frames that need them (--max-memory reaches them here).
    explicit AutoMethod(vk::Device& device, PpllOptions ppll = {});
    std::string name() const override { return "auto"; }
    bool exact() const override { return true; }
    // Which method rendered the last frame: "ppll" or "power-sorted".
    std::string last_choice() const { return chosen_->name(); }
    const PpllMethod& ppll() const { return ppll_; }

    // The frame path's side: prepare() decides, then every call goes to the method chosen.
    const vk::SharedDescriptors& descriptors() const override { return chosen_->descriptors(); }
    bool has_list_stats() const override { return false; }  // the lists exist only on some frames
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override { return chosen_->record(cmd, ctx, step); }
    After after_step(FrameContext& ctx, int step) override { return chosen_->after_step(ctx, step); }
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    PpllMethod ppll_;
    SortedCompositor power_sorted_;
    GpuMethod* chosen_;
    double decide_ms_ = 0.0;
};

}  // namespace brume
