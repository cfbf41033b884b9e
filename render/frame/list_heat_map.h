// The depth complexity of a frame, per pixel: how many spheres' clipped intervals the pixel ray
// meets, which is the length of that pixel's ppll list (twice its surfaces). The preview draws it as
// a heat map over the view. A pass of its own (shaders/list_heat_map.frag), not a figure read from
// ppll: it works whatever method is shown, and ppll's passes stay as they are. It draws the same
// sphere impostors with ppll's append test and adds 1 per fragment into the HDR target's red
// channel (float addition is exact far past any list length), so the frame read back through the
// frame path holds the counts. Not in the method catalogue; its image is counts, not radiance.
#pragma once

#include "render/frame/gpu_method.h"

#include <cstdint>
#include <vector>

namespace brume {

class ListHeatMap : public GpuMethod {
public:
    explicit ListHeatMap(vk::Device& device);

    std::string name() const override { return "list-heat-map"; }
    bool exact() const override { return false; }
    // Red: the list length of each pixel (the mean over its sub-pixels when supersampled); green,
    // blue: 0.
    Image render(const Scene& scene, FrameStats* stats) override;
    using GpuMethod::render;

    void prepare(FrameContext&) override {}
    void report(FrameStats&, const FrameContext&) override {}
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;

private:
    vk::UniquePipeline pipeline_;
};

// Figures of a count image (ListHeatMap's red channel), as FrameStats gives them for ppll.
struct ListLengthFigures {
    double longest = 0.0;
    double mean = 0.0;             // over pixels with a non-empty list
    std::uint64_t total = 0;       // rounded sum: the fragments of the frame without supersampling
    std::uint64_t nonempty_pixels = 0;
};
ListLengthFigures list_length_figures(const Image& counts);
// The red channel rounded to whole lengths, row-major from the top row, as reference_list_lengths.
std::vector<std::uint32_t> list_lengths(const Image& counts);

}  // namespace brume
