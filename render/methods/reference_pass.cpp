#include "render/methods/reference_pass.h"

#include "fullscreen.vert.h"
#include "radiance_buffer.frag.h"
#include "render/reference.h"
#include "render/vk/pipelines.h"

#include <chrono>

namespace brume {

using namespace vk;

ReferencePass::ReferencePass(Device& device, int threads) : GpuMethod(device), threads_(threads) {
    GraphicsPipelineDesc composite;
    composite.name = "reference_composite";
    composite.vertex = BRUME_SPIRV(spv_fullscreen_vert);
    composite.fragment = BRUME_SPIRV(spv_radiance_buffer_frag);
    composite.color_formats = {FrameResources::kHdrFormat};
    composite_pipeline_ = create_graphics_pipeline(device_, descriptors_.pipeline_layout(), composite);
}

void ReferencePass::prepare(FrameContext& ctx) {
    const auto start = std::chrono::steady_clock::now();
    ReferenceOptions options;
    options.threads = threads_;
    // ctx.scene() is already at the target's size (the frame path supersamples by enlarging it).
    const Image image = render_reference(ctx.scene(), options);
    const VkExtent2D extent = ctx.extent();
    const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * 16;
    if (radiance_.size() != bytes) {
        radiance_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "reference.radiance");
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

bool ReferencePass::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    ctx.resolve_to_hdr(cmd, composite_pipeline_.get());
    ctx.mark(cmd, "composite");
    return true;
}

void ReferencePass::report(FrameStats& stats, const FrameContext&) {
    // The trace is the frame's work; it runs on the CPU, so it is listed beside the GPU passes.
    stats.passes.insert(stats.passes.begin(), {"reference (cpu)", trace_ms_});
    stats.memory_bytes = radiance_.size();
}

}  // namespace brume
