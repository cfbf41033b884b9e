#include "render/methods/auto_method.h"

#include "sim/sphere_overlap.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace brume {

AutoMethod::AutoMethod(vk::Device& device, AutoOptions options)
    : GpuMethod(device),
      options_(options),
      ppll_(device, options.ppll),
      trace_(device, CpuTracer::Fast, options.threads),
      power_sorted_(device, SortedCompositor::Billboard::Spherical, SortedCompositor::SortKey::PowerDistance),
      chosen_(&ppll_) {
    // A CPU device runs the GPU methods on the same cores as trace, with rasterisation and SIMD lanes
    // that wait for each other on top: there trace is expected to win, elsewhere ppll.
    VkPhysicalDeviceProperties properties{};
    vkGetPhysicalDeviceProperties(device.physical(), &properties);
    cpu_device_ = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    if (options_.allow_cpu && cpu_device_) first_ = kTrace;
    path_ = first_;
}

double AutoMethod::measured_cost(const std::string& path) const {
    if (path == "ppll") return cost_[kPpll];
    if (path == "trace") return cost_[kTrace];
    return -1.0;
}

// Whether two frames show the same scene, cheaply: the camera, the counts and up to 64 spheres
// spread over the list. Two different scenes that agree on all of it only delay a measurement.
std::uint64_t AutoMethod::fingerprint(const Scene& scene) const {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](double v) {
        h ^= std::bit_cast<std::uint64_t>(v);
        h *= 1099511628211ull;
    };
    const Camera& c = scene.camera;
    for (double v : {c.position.x, c.position.y, c.position.z, c.look_at.x, c.look_at.y, c.look_at.z, c.fov_y_deg,
                     double(c.width), double(c.height), double(scene.spheres.size()), double(scene.boxes.size())})
        mix(v);
    const std::size_t n = scene.spheres.size(), step = std::max<std::size_t>(1, n / 64);
    for (std::size_t k = 0; k < n; k += step) {
        const Sphere& s = scene.spheres[k];
        for (double v : {s.center.x, s.center.y, s.center.z, s.radius, s.extinction}) mix(v);
    }
    return h;
}

AutoMethod::Path AutoMethod::choose(bool scene_changed) {
    measuring_ = false;
    if (!options_.allow_cpu) return kPpll;
    if (cpu_device_ && !options_.measure_on_cpu) return kTrace;
    const Path second = first_ == kPpll ? kTrace : kPpll;
    if (cost_[first_] < 0.0) {  // the first intersecting frames: warm-up, then the first measurement
        measuring_ = true;
        return first_;
    }
    if (!scene_changed) return path_;
    ++changed_frames_;
    if (cost_[second] < 0.0) {
        measuring_ = true;
        return second;
    }
    const Path best = cost_[kTrace] < cost_[kPpll] ? kTrace : kPpll;
    measuring_ = true;  // the path taken keeps its figure up to date
    if (changed_frames_ % kRemeasureEvery == 0) return best == kPpll ? kTrace : kPpll;
    return best;
}

void AutoMethod::prepare(FrameContext& ctx) {
    frame_start_ = std::chrono::steady_clock::now();
    const Scene& scene = ctx.scene();
    const bool intersecting = find_intersecting_spheres(scene.spheres).has_value();
    if (!intersecting) {
        chosen_ = &power_sorted_;
        measuring_ = false;
    } else {
        const std::uint64_t print = fingerprint(scene);
        const bool changed = print != last_fingerprint_;
        last_fingerprint_ = print;
        path_ = choose(changed);
        chosen_ = path_ == kTrace ? static_cast<GpuMethod*>(&trace_) : &ppll_;
        // The measured cost is per fragment; a frame not measured (a CPU device) skips the estimate,
        // a pass over every sphere (30 ms at 1,000,000).
        if (measuring_) fragments_estimate_ = double(std::max<std::uint64_t>(estimate_fragments(scene), 1));
    }
    decide_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_).count();
    chosen_->prepare(ctx);
}

GpuMethod::After AutoMethod::after_step(FrameContext& ctx, int step) {
    const After after = chosen_->after_step(ctx, step);
    if (after == After::Done && measuring_) {
        // The whole frame on the wall clock: CPU work and the GPU's, as the user waits for it.
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_).count();
        if (warm_[path_]) cost_[path_] = ms / fragments_estimate_;
        warm_[path_] = true;
    }
    return after;
}

void AutoMethod::report(FrameStats& stats, const FrameContext& ctx) {
    chosen_->report(stats, ctx);
    // The decision is CPU work the frame cannot skip: it counts in the frame's time.
    stats.passes.insert(stats.passes.begin(), {"decide (cpu): " + last_choice(), decide_ms_});
}

}  // namespace brume
