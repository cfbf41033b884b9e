#include "render/methods/cpu_trace_pass.h"

#include "render/fast_tracer.h"
#include "render/reference.h"

#include <chrono>

namespace brume {

using namespace vk;

CpuTracePass::CpuTracePass(Device& device, CpuTracer tracer, int threads)
    : GpuMethod(device), tracer_(tracer), threads_(threads) {}

void CpuTracePass::prepare(FrameContext& ctx) {
    const auto start = std::chrono::steady_clock::now();
    // ctx.scene() is already at the target's size (the frame path supersamples by enlarging it).
    const VkExtent2D extent = ctx.extent();
    const std::size_t pixels = std::size_t(extent.width) * extent.height;
    const VkDeviceSize bytes = VkDeviceSize(pixels) * 16;
    if (radiance_.size() != bytes)
        radiance_ = Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload,
                           tracer_ == CpuTracer::Reference ? "reference.radiance" : "trace.radiance");
    float* out = radiance_.as<float>();
    if (tracer_ == CpuTracer::Reference) {
        ReferenceOptions options;
        options.threads = threads_;
        const Image image = render_reference(ctx.scene(), options);
        for (std::size_t p = 0; p < pixels; ++p) {
            out[4 * p + 0] = image.rgb[3 * p + 0];
            out[4 * p + 1] = image.rgb[3 * p + 1];
            out[4 * p + 2] = image.rgb[3 * p + 2];
            out[4 * p + 3] = 1.0f;
        }
    } else {
        FastTraceOptions options;
        options.threads = threads_;
        options.scratch = &trace_scratch_;  // the last frame's memory
        options.sun = &ctx.sun_light();     // the frame's, built once
        render_fast_trace_rgba(ctx.scene(), options, out);  // straight into the upload buffer
    }
    trace_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool CpuTracePass::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    ctx.copy_to_hdr(cmd, radiance_.get());
    ctx.mark(cmd, "composite");
    return true;
}

void CpuTracePass::report(FrameStats& stats, const FrameContext&) {
    // The trace is the frame's work; it runs on the CPU, so it is listed beside the GPU passes.
    stats.passes.insert(stats.passes.begin(), {name() + " (cpu)", trace_ms_});
    stats.memory_bytes = radiance_.size();
}

}  // namespace brume
