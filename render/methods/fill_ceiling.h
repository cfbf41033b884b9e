// Not a renderer: the fill ceiling that `brume bench layers` prints beside each method. It draws the
// same sphere impostors as ppll's particle pass with a fragment shader that does no work but cannot
// be skipped (shaders/fill_ceiling.frag), so its time is what rasterising the scene's fragments
// costs on this device, the floor under any method that draws the spheres once. Not in the method
// catalogue; its image means nothing.
#pragma once

#include "render/frame/gpu_method.h"

namespace brume {

class FillCeiling : public GpuMethod {
public:
    explicit FillCeiling(vk::Device& device);

    std::string name() const override { return "fill-ceiling"; }
    bool exact() const override { return false; }
    Image render(const Scene& scene, FrameStats* stats) override;
    using GpuMethod::render;

    void prepare(FrameContext&) override {}
    void report(FrameStats&, const FrameContext&) override {}
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;

private:
    vk::UniquePipeline pipeline_;
};

}  // namespace brume
