// The contract between the frame path and a GPU method. The frame path (render/frame/frame_path.h)
// uploads the scene, records the passes every method shares, submits, waits, loops and sends the
// pixels where they go; a method only records its own passes into the command buffer it is handed and
// reads its own results once a submission completed. Nothing under render/methods/ submits work or
// reads the image back.
//
// One frame, as the frame path runs it:
//   prepare(ctx)                       CPU work and the method's own resources for this scene
//   loop (an attempt):
//     record(cmd, ctx, step = 0, 1, ...)  after the shared passes (opaque, light); returns true once
//                                         the HDR target holds the frame
//     after_step(ctx, step)           Done, NextStep (record step + 1 in a new submission: peel checks
//                                         its early stop between steps), or Again (the whole frame
//                                         again: ppll after its pool grew, auto after its path
//                                         refused the frame; the frame's bindings are written
//                                         into descriptors() again first)
//   report(stats, ctx)                 the method's own figures and pass names
#pragma once

#include "render/frame/frame_resources.h"
#include "render/frame/frame_stats.h"
#include "render/frame/pass_clock.h"
#include "render/methods/method.h"
#include "render/vk/descriptors.h"
#include "render/vk/device.h"

#include <cstdint>
#include <memory>
#include <string>

namespace brume {

class FramePath;
class GpuMethod;

// What a method is handed for one frame.
class FrameContext {
public:
    FrameContext(const Scene& scene, FrameResources& frame, const GpuMethod& method, PassClock& clock, bool stats,
                 bool list_stats)
        : scene_(scene), frame_(frame), method_(method), clock_(clock), stats_(stats), list_stats_(list_stats) {}

    const Scene& scene() const { return scene_; }
    VkExtent2D extent() const { return frame_.extent(); }
    std::uint32_t sphere_count() const { return frame_.sphere_count(); }
    // The scene's sun, built once a frame by the frame's upload (render/sun_light.h).
    const SunLight& sun_light() const { return frame_.sun_light(); }
    // The frame's uniforms, written from the scene; a method sets `pool` and `params` in prepare().
    gpu::FrameUniforms& uniforms() { return frame_.uniforms(); }
    // Builds and uploads the accurate shadow technique's light-space depth map (render/sun_depth_map.h)
    // for this frame, once; a method whose resolve reads it (exact_integrator.glsl with ACCURATE_SHADOWS)
    // calls this from prepare(). Nothing without shadows by that technique.
    void need_sun_depth_map() { frame_.ensure_sun_depth_map(scene_); }
    // Whether FrameStats were asked for, and the list statistics that cost extra atomics.
    bool stats_wanted() const { return stats_; }
    bool list_stats_wanted() const { return stats_ && list_stats_; }

    // Binds the method's descriptor set (the frame's bindings are written into it).
    void bind(VkCommandBuffer cmd) const;
    // The same set for compute pipelines.
    void bind_compute(VkCommandBuffer cmd) const;
    void draw_spheres(VkCommandBuffer cmd, VkPipeline pipeline) const;
    void begin_hdr_rendering(VkCommandBuffer cmd) const { frame_.begin_hdr_rendering(cmd); }
    void end_hdr_rendering(VkCommandBuffer cmd) const { frame_.end_hdr_rendering(cmd); }
    void resolve_to_hdr(VkCommandBuffer cmd, VkPipeline pipeline) const;
    void copy_to_hdr(VkCommandBuffer cmd, VkBuffer radiance) const { frame_.copy_to_hdr(cmd, radiance); }
    // Ends the GPU pass named `pass` (FrameStats::passes).
    void mark(VkCommandBuffer cmd, std::string pass) const { clock_.mark(cmd, std::move(pass)); }

private:
    const Scene& scene_;
    FrameResources& frame_;
    const GpuMethod& method_;
    PassClock& clock_;
    bool stats_, list_stats_;
};

class GpuMethod : public Method {
public:
    enum class After { Done, NextStep, Again };

    explicit GpuMethod(vk::Device& device);
    ~GpuMethod() override;

    using Method::render;
    // Renders through this method's own frame path and reads the image back.
    Image render(const Scene& scene, FrameStats* stats) override;
    GpuMethod* gpu() override { return this; }

    // --- The frame path's side (see the top of this file). ---
    // The set the method's pipelines bind; after prepare() the frame path writes its own bindings
    // into it (auto answers with the set of the method it chose in prepare()).
    virtual const vk::SharedDescriptors& descriptors() const { return descriptors_; }
    // Whether this method gathers list statistics (the frame path asks only methods that can).
    virtual bool has_list_stats() const { return false; }
    // Whether this method reads the shared opaque pass (the boxes' radiance and distance). A CPU tracer
    // finds its own boxes, and on a CPU device that pass costs as much as tracing a light scene.
    // Asked after prepare().
    virtual bool uses_opaque_pass() const { return true; }
    // Whether this method's passes read the per-sphere shadow technique's T_sun at the spheres' centres
    // (FrameResources::ensure_sphere_sun; the comparison methods shade by it in every technique).
    // A CPU tracer takes the scene's light itself. Asked after prepare().
    virtual bool reads_sphere_sun() const { return true; }
    virtual void prepare(FrameContext& ctx) = 0;
    virtual bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) = 0;
    virtual After after_step(FrameContext&, int) { return After::Done; }
    // `stats` holds the frame path's figures (passes as marked) when this is called.
    virtual void report(FrameStats& stats, const FrameContext& ctx) = 0;

protected:
    FramePath& own_path();

    vk::Device& device_;
    vk::SharedDescriptors descriptors_;

private:
    std::unique_ptr<FramePath> own_path_;  // made on the first render()
};

}  // namespace brume
