// A CPU tracer as a step of the frame path: the frame is traced on the CPU in prepare() into an upload
// buffer and copied into the HDR target, so a presenter or the readback sees it as any GPU method's frame.
// Two tracers: the double-precision reference (render/reference.h), which `auto` may take, and the
// float `trace` (render/fast_tracer.h), the fastest exact path on a CPU device such as lavapipe
// (docs/performance.md, "trace").
#pragma once

#include "render/fast_tracer.h"
#include "render/frame/gpu_method.h"
#include "render/vk/resources.h"

namespace brume {

enum class CpuTracer {
    Reference,  // render_reference: double precision, the ground truth
    Fast,       // render_fast_trace: float, heap-merged in bound order, stops early
};

class CpuTracePass : public GpuMethod {
public:
    CpuTracePass(vk::Device& device, CpuTracer tracer, int threads = 0);
    std::string name() const override { return tracer_ == CpuTracer::Reference ? "reference" : "trace"; }
    bool exact() const override { return true; }
    using GpuMethod::render;

    bool uses_opaque_pass() const override { return false; }  // the tracers meet the boxes themselves
    bool reads_sphere_sun() const override { return false; }  // nor do they read the GPU's spheres
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    CpuTracer tracer_;
    int threads_;
    vk::Buffer radiance_;
    FastTraceScratch trace_scratch_;  // trace's memory from frame to frame
    double trace_ms_ = 0.0;
};

}  // namespace brume
