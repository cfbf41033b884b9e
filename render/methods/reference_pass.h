// The CPU double-precision reference (render/reference.h) as a step of the frame path: the frame is
// traced on the CPU in prepare(), uploaded, and drawn into the HDR target, so a presenter or the
// readback sees it as any GPU method's frame. `auto` takes it on frames where it is the fastest
// exact path on this device (on a CPU device such as lavapipe it often is: docs/performance.md).
#pragma once

#include "render/frame/gpu_method.h"
#include "render/vk/resources.h"

namespace brume {

class ReferencePass : public GpuMethod {
public:
    explicit ReferencePass(vk::Device& device, int threads = 0);
    std::string name() const override { return "reference"; }
    bool exact() const override { return true; }
    using GpuMethod::render;

    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    int threads_;
    vk::UniquePipeline composite_pipeline_;
    vk::Buffer radiance_;
    double trace_ms_ = 0.0;
};

}  // namespace brume
