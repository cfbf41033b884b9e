#include "render/methods/fill_ceiling.h"

#include "fill_ceiling.frag.h"
#include "render/frame/frame_path.h"
#include "render/frame/frame_resources.h"
#include "render/vk/pipelines.h"
#include "sphere_impostor.vert.h"

namespace brume {

using namespace vk;

FillCeiling::FillCeiling(Device& device) : GpuMethod(device) {
    GraphicsPipelineDesc desc;
    desc.name = "fill_ceiling";
    desc.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    desc.fragment = BRUME_SPIRV(spv_fill_ceiling_frag);
    desc.color_formats = {FrameResources::kHdrFormat};
    pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), desc);
}

Image FillCeiling::render(const Scene& scene, FrameStats* stats) { return own_path().render(*this, scene, stats, false); }

bool FillCeiling::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    ctx.begin_hdr_rendering(cmd);
    ctx.draw_spheres(cmd, pipeline_);
    ctx.end_hdr_rendering(cmd);
    ctx.mark(cmd, "particles");
    return true;
}

}  // namespace brume
