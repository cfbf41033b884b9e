#include "render/methods/auto_method.h"

#include "sim/sphere_overlap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace brume {

AutoMethod::AutoMethod(vk::Device& device, AutoOptions options)
    : GpuMethod(device),
      options_(options),
      ppll_(device, options.ppll),
      tiles_(device, options.tiles),
      trace_(device, CpuTracer::Fast, options.threads),
      power_sorted_(device, SortedCompositor::Billboard::Spherical, SortedCompositor::SortKey::PowerDistance),
      chosen_(&ppll_) {
    // A CPU device runs the GPU methods on the same cores as trace, with rasterisation and SIMD lanes
    // that wait for each other on top: there trace is expected to win, and of the GPU paths ppll
    // (tiles was the slower on lavapipe). On a GPU, tiles, then ppll: docs/performance.md.
    VkPhysicalDeviceProperties properties{};
    vkGetPhysicalDeviceProperties(device.physical(), &properties);
    cpu_device_ = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    if (cpu_device_) {
        if (options_.allow_cpu) candidates_.push_back(kTrace);
        candidates_.push_back(kPpll);
        if (options_.measure_on_cpu) candidates_.push_back(kTiles);
        else candidates_.resize(1);  // unmeasured: the first is the only one taken
    } else {
        candidates_ = {kTiles, kPpll};
        if (options_.allow_cpu) candidates_.push_back(kTrace);
    }
    path_ = candidates_.front();
}

double AutoMethod::measured_cost(const std::string& path) const {
    if (path == "tiles") return cost_[kTiles];
    if (path == "ppll") return cost_[kPpll];
    if (path == "trace") return cost_[kTrace];
    return -1.0;
}

GpuMethod& AutoMethod::method_of(Path path) {
    switch (path) {
    case kTiles: return tiles_;
    case kPpll: return ppll_;
    default: return trace_;
    }
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
    if (candidates_.size() == 1) return candidates_.front();
    const Path first = candidates_.front();
    if (cost_[first] < 0.0) {  // the first intersecting frames: warm-up, then the first measurement
        measuring_ = true;
        return first;
    }
    if (!scene_changed) return path_;
    ++changed_frames_;
    measuring_ = true;  // from here on the path taken keeps its figure up to date
    for (Path p : candidates_)
        if (cost_[p] < 0.0) return p;  // not yet measured (its first frame is its warm-up)
    Path best = first;
    for (Path p : candidates_)
        if (cost_[p] < cost_[best]) best = p;
    // Another path whose turn has come is measured again: the scene may have moved in its favour (or a
    // path that refused may take this scene now). The earliest due first.
    std::optional<Path> due;
    for (Path p : candidates_)
        if (p != best && due_[p] <= changed_frames_ && (!due || due_[p] < due_[*due])) due = p;
    return due ? *due : best;
}

int AutoMethod::remeasure_interval(double cost, double best) {
    double factor = kMaxRemeasureFactor;
    if (cost < std::numeric_limits<double>::infinity() && best > 0.0) factor = std::ceil(cost / best);
    return kRemeasureEvery * int(std::clamp(factor, 1.0, double(kMaxRemeasureFactor)));
}

bool AutoMethod::fall_back() {
    cost_[path_] = std::numeric_limits<double>::infinity();  // the slowest until measured again
    due_[path_] = changed_frames_ + remeasure_interval(cost_[path_], 0.0);
    measuring_ = false;  // this frame's time holds the refused attempt
    // The fastest path measured that this frame has not tried, else the next unmeasured one in order.
    std::optional<Path> next;
    for (Path p : candidates_)
        if (!tried_[p] && cost_[p] >= 0.0 && cost_[p] < std::numeric_limits<double>::infinity() &&
            (!next || cost_[p] < cost_[*next]))
            next = p;
    if (!next)
        for (Path p : candidates_)
            if (!tried_[p] && cost_[p] < 0.0) {
                next = p;
                break;
            }
    if (!next) return false;
    path_ = *next;
    tried_[path_] = true;
    chosen_ = &method_of(path_);
    return true;
}

void AutoMethod::prepare_chosen(FrameContext& ctx) {
    // A path whose budget the scene exceeds says so here (tiles' lists, ppll's first pool).
    for (;;) {
        try {
            chosen_->prepare(ctx);
            return;
        } catch (const TileBudgetError&) {
            if (!fall_back()) throw;
        } catch (const PoolBudgetError&) {
            if (!fall_back()) throw;
        }
    }
}

bool AutoMethod::takes_power_sorted(const Scene& scene) const {
    // On a CPU device trace is the faster on disjoint spheres too, and it needs no test for them:
    // lavapipe's compositing took 2.2-4.3x trace's frame (disjoint-300 at 160x120, 640x360 and
    // 1280x720; two disjoint spheres of radii 0.9 and 15, and 21,603 disjoint snowflakes, at 640x360,
    // where the sweep-and-prune test alone took 9 ms; docs/methods.md, "auto").
    if (cpu_device_ && options_.allow_cpu) return false;
    // The compositor lights a sphere by one sun transmittance, the per-sphere technique's: exact without
    // shadows and for that technique, not for the accurate one, whose T_sun varies across a sphere.
    if (scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::Accurate) return false;
    return !find_intersecting_spheres(scene.spheres).has_value();
}

void AutoMethod::prepare(FrameContext& ctx) {
    frame_start_ = std::chrono::steady_clock::now();
    const Scene& scene = ctx.scene();
    if (takes_power_sorted(scene)) {
        chosen_ = &power_sorted_;
        measuring_ = false;
        decide_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_).count();
        chosen_->prepare(ctx);
        return;
    }
    const std::uint64_t print = fingerprint(scene);
    const bool changed = print != last_fingerprint_;
    last_fingerprint_ = print;
    path_ = choose(changed);
    chosen_ = &method_of(path_);
    tried_ = {};
    tried_[path_] = true;
    // The measured cost is per fragment; a frame not measured (a CPU device) skips the estimate,
    // a pass over every sphere (30 ms at 1,000,000).
    if (measuring_) fragments_estimate_ = double(std::max<std::uint64_t>(estimate_fragments(scene), 1));
    decide_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_).count();
    prepare_chosen(ctx);
}

GpuMethod::After AutoMethod::after_step(FrameContext& ctx, int step) {
    After after = After::Done;
    try {
        after = chosen_->after_step(ctx, step);
    } catch (const ListResolveError&) {
        // The frame was refused, never written wrong: another path renders it from the start (the
        // frame path writes its bindings into the new path's set before it records again).
        if (chosen_ == &power_sorted_ || !fall_back()) throw;
        prepare_chosen(ctx);
        return After::Again;
    } catch (const PoolBudgetError&) {
        if (chosen_ == &power_sorted_ || !fall_back()) throw;
        prepare_chosen(ctx);
        return After::Again;
    }
    if (after == After::Done && measuring_) {
        // The whole frame on the wall clock: CPU work and the GPU's, as the user waits for it.
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_).count();
        if (warm_[path_]) {
            cost_[path_] = ms / fragments_estimate_;
            // Its next measurement, should it not be the fastest: later the slower it was.
            double best_other = std::numeric_limits<double>::infinity();
            for (Path p : candidates_)
                if (p != path_ && cost_[p] >= 0.0) best_other = std::min(best_other, cost_[p]);
            due_[path_] = changed_frames_ + remeasure_interval(cost_[path_], best_other);
        }
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
