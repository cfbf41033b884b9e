#include "render/frame/list_heat_map.h"

#include "list_heat_map.frag.h"
#include "render/frame/frame_path.h"
#include "render/frame/frame_resources.h"
#include "render/vk/pipelines.h"
#include "sphere_impostor.vert.h"

#include <algorithm>
#include <cmath>

namespace brume {

using namespace vk;

ListHeatMap::ListHeatMap(Device& device) : GpuMethod(device) {
    GraphicsPipelineDesc desc;
    desc.name = "list_heat_map";
    desc.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    desc.fragment = BRUME_SPIRV(spv_list_heat_map_frag);
    desc.color_formats = {FrameResources::kHdrFormat};
    desc.blends = {blend_additive()};
    pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), desc);
}

Image ListHeatMap::render(const Scene& scene, FrameStats* stats) { return own_path().render(*this, scene, stats, false); }

bool ListHeatMap::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    ctx.begin_hdr_rendering(cmd);
    // The target's contents are undefined when rendering begins: the counts start from 0.
    VkClearAttachment clear{};
    clear.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
    clear.colorAttachment = 0;
    clear.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    VkClearRect rect{};
    rect.rect = {{0, 0}, ctx.extent()};
    rect.layerCount = 1;
    vkCmdClearAttachments(cmd, 1, &clear, 1, &rect);
    ctx.draw_spheres(cmd, pipeline_);
    ctx.end_hdr_rendering(cmd);
    ctx.mark(cmd, "list heat map");
    return true;
}

ListLengthFigures list_length_figures(const Image& counts) {
    ListLengthFigures f;
    double sum = 0.0;
    for (int j = 0; j < counts.height; ++j)
        for (int i = 0; i < counts.width; ++i) {
            const double n = counts.pixel(i, j)[0];
            if (!(n > 0.0)) continue;
            f.longest = std::max(f.longest, n);
            sum += n;
            ++f.nonempty_pixels;
        }
    f.total = std::uint64_t(std::llround(sum));
    f.mean = f.nonempty_pixels ? sum / double(f.nonempty_pixels) : 0.0;
    return f;
}

std::vector<std::uint32_t> list_lengths(const Image& counts) {
    std::vector<std::uint32_t> out(std::size_t(counts.width) * std::size_t(counts.height));
    for (int j = 0; j < counts.height; ++j)
        for (int i = 0; i < counts.width; ++i)
            out[std::size_t(j) * std::size_t(counts.width) + std::size_t(i)] =
                std::uint32_t(std::lround(std::max(0.0f, counts.pixel(i, j)[0])));
    return out;
}

}  // namespace brume
