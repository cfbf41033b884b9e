// The light pass's fill of the accurate shadow technique's depth map on the device
// (shaders/sun_map_build.comp): the host plans the lattice (SunDepthMap::plan) and FrameResources writes
// its header and room into the sun buffer; this pass fills the vertices, an invocation a column, before
// any method pass reads them. On a CPU device (lavapipe) the host's build is the faster code, so the
// frame path takes it there (docs/performance.md, "The light's CPU preparation in a GPU method's frame").
#pragma once

#include "render/sun_depth_map.h"
#include "render/sun_light.h"
#include "render/vk/descriptors.h"
#include "render/vk/device.h"
#include "render/vk/handle.h"
#include "sim/scene.h"

namespace brume {

class SunMapPass {
public:
    // Whether the device fills the map on `device`: not on a CPU device, unless BRUME_SUN_MAP says
    // (`device` or `host`; another value is refused with std::invalid_argument).
    static bool wanted_on(const vk::Device& device);

    // The pipeline, on the shared descriptor layout (the frame's bindings: uniforms, spheres, the sun
    // buffer, which it writes).
    SunMapPass(const vk::Device& device, const vk::SharedDescriptors& descriptors);

    // Whether each invocation of the fill of `map` (planned) stays within its loop budget: the column's
    // vertices twice and, for each sphere of the sun grid's fullest cell, the cells of the longest
    // chord. lavapipe cuts a shader's loops after 65,535 iterations, silently; on a GPU a column that
    // long would keep one thread busy for the frame. Where it does not fit, the host builds the map.
    bool fits(const Scene& scene, const SunLight& sun, const SunDepthMap& map) const;

    // Records the fill of `map` (its header already in the sun buffer bound to `descriptors`), then
    // the barrier before the resolves that read it (ppll's fragment shader, tiles' compute shader).
    void record(VkCommandBuffer cmd, const vk::SharedDescriptors& descriptors, const SunDepthMap& map) const;

private:
    const vk::Device& device_;
    vk::UniquePipeline pipeline_;
};

}  // namespace brume
