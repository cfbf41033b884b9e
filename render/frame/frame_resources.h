// What every method shares for one scene at one resolution: the uploaded scene (uniforms, spheres,
// boxes), the opaque pass and its output (radiance + distance per pixel), and the linear HDR target
// that a method resolves into. Owned by the frame path (render/frame/frame_path.h): a headless frame
// copies the target back into an Image, a presenter samples it to tone-map it into a window.
#pragma once

#include <vector>

#include "render/frame/sun_map_pass.h"
#include "render/image.h"
#include "render/sun_depth_map.h"
#include "render/vk/descriptors.h"
#include "render/vk/device.h"
#include "render/vk/gpu_types.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

namespace brume {

class FrameResources {
public:
    static constexpr VkFormat kOpaqueFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // rgb radiance, a distance
    static constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
    static constexpr VkFormat kHdrFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

    explicit FrameResources(const vk::Device& device);

    // Uploads the scene, (re)creating buffers and images whose size changed (after waiting for the
    // device, since a presenter's pass may still read the old HDR target). Every uniform is
    // rewritten from the scene; a method sets its own (pool, params) afterwards.
    void upload(const Scene& scene);
    // The accurate shadow technique's depth map for the scene last uploaded, built and written after
    // the sun grid on the first call of a frame (the CPU tracers build their own, so a frame path
    // builds it only for the methods that read it: FrameContext::need_sun_depth_map).
    void ensure_sun_depth_map(const Scene& scene);
    // Where the depth map is filled: on a GPU by the device (the frame path's light pass records
    // record_sun_map_build, render/frame/sun_map_pass.h, after the CPU planned its lattice); on a CPU
    // device by the host's build, which is faster there. BRUME_SUN_MAP=device|host overrides it.
    bool sun_map_on_device() const { return sun_map_pass_.has_value(); }
    // Records the device's fill of this frame's map and the barrier before the resolves that read it;
    // false (nothing recorded) where the host built it or there is none.
    bool record_sun_map_build(VkCommandBuffer cmd) const;
    // The per-sphere shadow technique's T_sun at each sphere's centre (GpuSphere emission_sun.w, which
    // upload() leaves at 1), for the scene last uploaded, written on the first call of a frame: the
    // frame path asks for it before any method that reads it records (GpuMethod::reads_sphere_sun).
    // Computed in double by the reference's per-sphere code, a walk over the spheres above each
    // centre: on vdb-cloud (6,152 spheres) 9.6 ms of a preview frame whose trace never read it.
    void ensure_sphere_sun(const Scene& scene);
    // The sun's light-space grid (render/sun_light.h) copied into the sun buffer, for the scene last
    // uploaded, on the first call of a frame: the opaque pass reads it (exact T_sun at lit box hits),
    // and the depth map goes after it (ensure_sun_depth_map calls this first). A frame traced on the
    // CPU never asks, and its SunLight never builds the grid.
    void ensure_sun_grid();
    // The CPU time each of the three above took this frame (since upload), wall clock; negative where
    // it built nothing (no shadows, another technique, or no reader). No GPU pass times this work, yet
    // every frame that reads it waits for it: FramePath::run lists it among the frame's passes as
    // "(cpu)" passes, as a method lists its CPU sort, so that a frame's total and a shadow technique's
    // cost against the unshadowed frame count it (the depth map's build is most of what the accurate
    // technique adds on the CPU side: docs/performance.md).
    struct LightPrepTimes {
        double sun_grid_ms = -1.0;
        double sphere_sun_ms = -1.0;
        double sun_map_ms = -1.0;
    };
    const LightPrepTimes& light_prep_times() const { return light_prep_; }
    // Writes the frame's bindings (uniforms, spheres, boxes, opaque image) into a method's set.
    void write_frame_bindings(const vk::SharedDescriptors& descriptors) const;

    gpu::FrameUniforms& uniforms() { return *uniform_buffer_.as<gpu::FrameUniforms>(); }
    VkExtent2D extent() const { return extent_; }
    std::uint32_t sphere_count() const { return sphere_count_; }
    // The scene's sun (render/sun_light.h) as upload() built it, for a CPU tracer to reuse.
    const SunLight& sun_light() const { return *sun_light_; }

    // Clears the opaque image to (background, +inf) and draws the boxes into it.
    void record_opaque_pass(VkCommandBuffer cmd) const;
    // Begins dynamic rendering into the HDR target (contents undefined: the resolve writes every
    // pixel). Its barrier also orders the write after a presenter's reads of the previous frame.
    void begin_hdr_rendering(VkCommandBuffer cmd) const;
    void end_hdr_rendering(VkCommandBuffer cmd) const;
    // Inside a rendering scope: one impostor (6 vertices) per sphere with `pipeline` and the
    // method's descriptor set; nothing when the scene has no spheres.
    void draw_spheres(VkCommandBuffer cmd, VkPipeline pipeline, const vk::SharedDescriptors& descriptors) const;
    // The usual last pass of a method: one fullscreen triangle with `pipeline` into the HDR target.
    void resolve_to_hdr(VkCommandBuffer cmd, VkPipeline pipeline, const vk::SharedDescriptors& descriptors) const;
    // A frame made elsewhere (the CPU tracers): `radiance`, RGBA32F pixels row by row at the target's
    // size (a TRANSFER_SRC buffer), copied into the HDR target, which is left as a resolve leaves it.
    // A copy, not a fullscreen draw: on lavapipe the draw took 10-15% of a 2-layer trace frame.
    void copy_to_hdr(VkCommandBuffer cmd, VkBuffer radiance) const;

    // After the method's last pass: copies the HDR target into host memory (read_hdr() once the
    // frame completed), or makes it readable by a presenter's sampler.
    void record_hdr_readback(VkCommandBuffer cmd) const;
    Image read_hdr() const;
    void record_hdr_to_sampled(VkCommandBuffer cmd) const;
    VkImageView hdr_view() const { return hdr_image_.view(); }

private:
    const vk::Device& device_;
    vk::SharedDescriptors descriptors_;  // the opaque pass's own set: the frame bindings only
    vk::UniquePipeline opaque_pipeline_;
    std::optional<SunMapPass> sun_map_pass_;  // where the device fills the map (SunMapPass::wanted_on)
    bool sun_map_pending_ = false;  // this frame's map is planned, for the light pass to fill
    vk::Buffer uniform_buffer_;
    vk::Buffer sphere_buffer_;
    vk::Buffer box_buffer_;
    vk::Buffer sun_grid_buffer_;  // shaders/shared.h SunGridHeader, then the grid's offsets and sphere list
    // What the sun buffer holds this frame: the header, the grid's words, and whether the depth map
    // was added after them (ensure_sun_depth_map).
    gpu::SunGridHeader sun_header_{};
    std::vector<std::uint32_t> sun_grid_words_;
    bool sun_grid_done_ = false;
    bool sun_depth_map_done_ = false;
    std::size_t map_words_room_ = 0;  // the last depth map's size: room kept for it in the sun buffer
    std::size_t sun_map_words_ = 0;   // the words after the grid this frame: the map's and its columns'
    std::vector<std::uint32_t> sun_column_words_;  // this frame's columns as the device reads them
    std::unique_ptr<SunLight> sun_light_;  // the scene's, from upload()
    glm::dvec3 eye_{0.0};                  // the scene's eye: the device's origin (render/vk/gpu_types.h)
    bool sphere_sun_done_ = true;          // ensure_sphere_sun wrote this frame's, or none are needed
    SunDepthMap sun_depth_map_;  // kept from frame to frame for its memory (ensure_sun_depth_map)
    LightPrepTimes light_prep_;  // this frame's (upload resets it)
    // Writes the header and the grid words, then `map` (may be empty) after them, in room for at least
    // map_room words, then `columns` (a sparse cloud's, SunGridHeader.column_size), growing the buffer
    // when it must (after waiting for the device) and rewriting the opaque pass's set then.
    void write_sun_buffer(std::span<const float> map, std::size_t map_room = 0,
                          std::span<const std::uint32_t> columns = {});
    vk::DeviceImage opaque_image_;
    vk::DeviceImage depth_image_;
    vk::DeviceImage hdr_image_;
    vk::Buffer hdr_readback_;
    VkExtent2D extent_{};
    std::uint32_t sphere_count_ = 0;
    std::uint32_t box_count_ = 0;
    glm::vec3 background_{0.0f};
};

}  // namespace brume
