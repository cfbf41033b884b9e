// The one path a frame takes, for every GPU method (docs/architecture.md):
//   1. upload the scene (FrameResources);
//   2. the method's prepare(), then the frame's bindings written into the method's set;
//   3. the shared passes, recorded before any method pass: the opaque pass, then the light pass
//      slot (record_shared_passes: on a GPU the accurate shadows' depth map is filled there,
//      render/frame/sun_map_pass.h);
//   4. the method's steps, each submitted and waited for, with the overflow loop (a method may ask
//      for the whole frame again, as ppll does when its pool regrows);
//   5. the pixels: read back into an Image (render, play, bench), or left in the sampled HDR target
//      for a Presenter that draws it into a window;
//   6. the same FrameStats for every method: GPU time per named pass, the CPU work those passes
//      waited for as "(cpu)" passes (the light's preparation, a method's sort), regrows, the
//      method's figures.
// Submissions go through a ring of frame slots (render/vk/frame_ring.h), so a presented frame can
// still be on its way to the screen while the next one is recorded.
#pragma once

#include "render/frame/frame_resources.h"
#include "render/frame/frame_stats.h"
#include "render/frame/gpu_method.h"
#include "render/frame/pass_clock.h"
#include "render/frame/presenter.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/frame_ring.h"
#include "sim/scene.h"

#include <cstdint>

namespace brume {

class FramePath {
public:
    explicit FramePath(vk::Device& device, std::uint32_t frames_in_flight = vk::FrameRing::kDefaultSlots);
    ~FramePath();

    // Renders one frame with `method` and reads it back. `list_stats` asks methods that keep
    // per-pixel lists for their list-length figures (extra atomics).
    Image render(GpuMethod& method, const Scene& scene, FrameStats* stats = nullptr, bool list_stats = true);
    // Renders one frame with `method` and hands it to `presenter`. Returns what present() returned.
    // `list_stats` as for render(), off by default: a window shows frames, the preview's panel asks.
    bool render_to(Presenter& presenter, GpuMethod& method, const Scene& scene, FrameStats* stats = nullptr,
                   bool list_stats = false);

    const FrameResources& resources() const { return resources_; }
    // Wall-clock milliseconds the last frame spent uploading its scene (the preview's "upload").
    double last_upload_ms() const { return upload_ms_; }
    vk::Device& device() const { return device_; }

private:
    enum class Output { Readback, Sampled };
    void run(GpuMethod& method, const Scene& scene, FrameStats* stats, bool list_stats, Output output);
    void record_shared_passes(VkCommandBuffer cmd, FrameContext& ctx, const GpuMethod& method);

    vk::Device& device_;
    vk::FrameRing ring_;
    FrameResources resources_;
    PassClock clock_;
    double upload_ms_ = 0.0;
};

}  // namespace brume
