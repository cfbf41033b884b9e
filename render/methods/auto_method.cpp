#include "render/methods/auto_method.h"

#include "sim/sphere_overlap.h"

#include <chrono>

namespace brume {

AutoMethod::AutoMethod(vk::Device& device, PpllOptions ppll)
    : GpuMethod(device),
      ppll_(device, ppll),
      power_sorted_(device, SortedCompositor::Billboard::Spherical, SortedCompositor::SortKey::PowerDistance),
      chosen_(&ppll_) {}

void AutoMethod::prepare(FrameContext& ctx) {
    const auto start = std::chrono::steady_clock::now();
    const bool intersecting = find_intersecting_spheres(ctx.scene().spheres).has_value();
    decide_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    chosen_ = intersecting ? static_cast<GpuMethod*>(&ppll_) : &power_sorted_;
    chosen_->prepare(ctx);
}

void AutoMethod::report(FrameStats& stats, const FrameContext& ctx) {
    chosen_->report(stats, ctx);
    // The decision is CPU work the frame cannot skip: it counts in the frame's time.
    stats.passes.insert(stats.passes.begin(), {"decide (cpu): " + last_choice(), decide_ms_});
}

}  // namespace brume
