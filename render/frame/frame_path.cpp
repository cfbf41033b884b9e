#include "render/frame/frame_path.h"

#include "render/supersample.h"
#include "render/vk/resources.h"

#include <chrono>
#include <stdexcept>

namespace brume {

FramePath::FramePath(vk::Device& device, std::uint32_t frames_in_flight)
    : device_(device), ring_(device, frames_in_flight), resources_(device), clock_(device) {}

FramePath::~FramePath() { ring_.wait_all(); }

// Supersampling: the method draws the scene at k times its size (render/supersample.h), so every
// method gets it without knowing; the readback averages the blocks, the presenter's tone map too.
Image FramePath::render(GpuMethod& method, const Scene& scene, FrameStats* stats, bool list_stats) {
    if (scene.camera.supersample == 1) {
        run(method, scene, stats, list_stats, Output::Readback);
        return resources_.read_hdr();
    }
    run(method, supersampled_scene(scene, int(device_.properties().limits.maxImageDimension2D)), stats, list_stats,
        Output::Readback);
    return average_blocks(resources_.read_hdr(), scene.camera.supersample);
}

bool FramePath::render_to(Presenter& presenter, GpuMethod& method, const Scene& scene, FrameStats* stats,
                          bool list_stats) {
    if (scene.camera.supersample == 1)
        run(method, scene, stats, list_stats, Output::Sampled);
    else
        run(method, supersampled_scene(scene, int(device_.properties().limits.maxImageDimension2D)), stats,
            list_stats, Output::Sampled);
    ring_.begin_again();
    return presenter.present(resources_, ring_);
}

void FramePath::record_shared_passes(VkCommandBuffer cmd, FrameContext& ctx, const GpuMethod& method) {
    if (method.uses_opaque_pass()) {
        resources_.record_opaque_pass(cmd);
        ctx.mark(cmd, "clear+opaque");
    }
    // The light pass slot: a pass that every method's shading reads (sun transmittance, a shadow
    // map) is recorded here, after the opaque pass and before any method pass. On a GPU the
    // accurate technique's depth map is filled here (FrameResources::record_sun_map_build).
    if (resources_.record_sun_map_build(cmd)) ctx.mark(cmd, "sun map");
}

void FramePath::run(GpuMethod& method, const Scene& scene, FrameStats* stats, bool list_stats, Output output) {
    // The previous frame's method passes completed before it returned; only a presenter's passes
    // may still run, and recording a slot waits for that slot's last use.
    const auto upload_start = std::chrono::steady_clock::now();
    resources_.upload(scene);
    upload_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - upload_start).count();
    FrameContext ctx(scene, resources_, method, clock_, stats != nullptr, list_stats && method.has_list_stats());
    method.prepare(ctx);
    if (method.uses_opaque_pass()) resources_.ensure_sun_grid();
    if (method.reads_sphere_sun()) resources_.ensure_sphere_sun(scene);
    // Every frame: a few descriptor writes, and no method's set is in use by then (only a
    // presenter's passes may still run, and they bind no method set).
    resources_.write_frame_bindings(method.descriptors());

    int regrows = 0;
    for (bool first_attempt = true;; first_attempt = false) {
        GpuMethod::After after = GpuMethod::After::Done;
        bool complete = false;
        for (int step = 0;; ++step) {
            VkCommandBuffer cmd = (step == 0 && first_attempt ? ring_.begin_next() : ring_.begin_again()).cmd;
            if (step == 0) {
                clock_.start(cmd);
                record_shared_passes(cmd, ctx, method);
            } else {
                // This submission reads and writes what the previous one wrote.
                vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                   VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                   VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
            }
            complete = method.record(cmd, ctx, step);
            if (complete) {
                if (output == Output::Readback)
                    resources_.record_hdr_readback(cmd);
                else
                    resources_.record_hdr_to_sampled(cmd);
            }
            ring_.submit();
            ring_.wait();
            after = method.after_step(ctx, step);
            if (after != GpuMethod::After::NextStep) break;
            if (complete) throw std::logic_error(method.name() + ": asked for another step after completing the frame");
        }
        if (after == GpuMethod::After::Again) {
            ++regrows;
            // The method may have replaced what its set points at (ppll's grown pool), or be another
            // set altogether (auto moving to another path after one refused the frame).
            if (method.uses_opaque_pass()) resources_.ensure_sun_grid();
            if (method.reads_sphere_sun()) resources_.ensure_sphere_sun(scene);
            resources_.write_frame_bindings(method.descriptors());
            continue;
        }
        if (!complete) throw std::logic_error(method.name() + ": finished a frame without completing the HDR target");
        break;
    }

    if (stats) {
        *stats = FrameStats{};
        stats->passes = clock_.passes();
        // The light's CPU preparation (the sun grid, the per-sphere T_sun, the depth map), which the
        // GPU passes wait for, before them; a method's own CPU passes (its sort) go first (report).
        const FrameResources::LightPrepTimes& light = resources_.light_prep_times();
        std::vector<PassTime> cpu;
        if (light.sun_grid_ms >= 0.0) cpu.push_back({"sun grid (cpu)", light.sun_grid_ms});
        if (light.sphere_sun_ms >= 0.0) cpu.push_back({"sphere sun (cpu)", light.sphere_sun_ms});
        if (light.sun_map_ms >= 0.0) cpu.push_back({"sun map (cpu)", light.sun_map_ms});
        stats->passes.insert(stats->passes.begin(), cpu.begin(), cpu.end());
        stats->regrows = regrows;
        method.report(*stats, ctx);
        stats->total_ms = 0.0;
        for (const PassTime& p : stats->passes) stats->total_ms += p.ms;
    }
}

}  // namespace brume
