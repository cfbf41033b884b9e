#include "render/methods/cpu_trace_pass.h"

#include "fullscreen.vert.h"
#include "radiance_buffer.frag.h"
#include "render/fast_tracer.h"
#include "render/reference.h"
#include "render/vk/pipelines.h"

#include <chrono>

namespace brume {

using namespace vk;

CpuTracePass::CpuTracePass(Device& device, CpuTracer tracer, int threads)
    : GpuMethod(device), tracer_(tracer), threads_(threads) {
    GraphicsPipelineDesc composite;
    composite.name = tracer == CpuTracer::Reference ? "reference_composite" : "trace_composite";
    composite.vertex = BRUME_SPIRV(spv_fullscreen_vert);
    composite.fragment = BRUME_SPIRV(spv_radiance_buffer_frag);
    composite.color_formats = {FrameResources::kHdrFormat};
    composite_pipeline_ = create_graphics_pipeline(device_, descriptors_.pipeline_layout(), composite);
}

void CpuTracePass::prepare(FrameContext& ctx) {
    const auto start = std::chrono::steady_clock::now();
    // ctx.scene() is already at the target's size (the frame path supersamples by enlarging it).
    Image image;
    if (tracer_ == CpuTracer::Reference) {
        ReferenceOptions options;
        options.threads = threads_;
        image = render_reference(ctx.scene(), options);
    } else {
        FastTraceOptions options;
        options.threads = threads_;
        image = render_fast_trace(ctx.scene(), options);
    }
    const VkExtent2D extent = ctx.extent();
    const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * 16;
    if (radiance_.size() != bytes) {
        radiance_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload,
                           tracer_ == CpuTracer::Reference ? "reference.radiance" : "trace.radiance");
        descriptors_.write_storage(gpu::BINDING_RADIANCE_BUFFER, radiance_.get());
    }
    float* out = radiance_.as<float>();
    for (std::size_t p = 0; p < std::size_t(extent.width) * extent.height; ++p) {
        out[4 * p + 0] = image.rgb[3 * p + 0];
        out[4 * p + 1] = image.rgb[3 * p + 1];
        out[4 * p + 2] = image.rgb[3 * p + 2];
        out[4 * p + 3] = 1.0f;
    }
    trace_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool CpuTracePass::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    ctx.resolve_to_hdr(cmd, composite_pipeline_.get());
    ctx.mark(cmd, "composite");
    return true;
}

void CpuTracePass::report(FrameStats& stats, const FrameContext&) {
    // The trace is the frame's work; it runs on the CPU, so it is listed beside the GPU passes.
    stats.passes.insert(stats.passes.begin(), {name() + " (cpu)", trace_ms_});
    stats.memory_bytes = radiance_.size();
}

}  // namespace brume
