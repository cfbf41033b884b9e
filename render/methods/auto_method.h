// `auto`: model no more than the frame needs, and take the fastest exact path on this device.
//
// When no two spheres on screen share volume, compositing whole spheres back to front in
// power-distance order (|c - eye|^2 - r^2) is exact, with each sphere's chord clipped by the eye and
// the opaque surface, and needs no per-pixel lists. The choice is made per frame on the CPU
// (sim/sphere_overlap.h, O(n log n); why: docs/decisions.md, "`auto` decides per frame on the CPU").
// Not with accurate shadows: the compositor lights a sphere by one sun transmittance (the per-sphere
// technique's), and the accurate technique's varies across it. Nor on a CPU device, where trace is
// 2.2-4.3x faster on disjoint spheres too and needs no test for them (takes_power_sorted).
//
// Frames with intersecting spheres take the fastest exact path measured on this device: `tiles`
// (compute, render/methods/tiles.h), ppll, or `trace`, the float CPU tracer (render/fast_tracer.h).
// On a CPU device such as lavapipe trace is the faster by far (docs/performance.md, "trace") and is
// taken without measuring: an image should not depend on the machine's load. On a GPU the paths are
// measured, tiles first: on an NVIDIA H200 it was 25-38x faster than ppll and 24-50x faster than the
// CPU reference on bench scale's clouds, where ppll was slower than that reference from 100,000
// spheres up (docs/performance.md, "On an NVIDIA H200"). A path's first frame is a warm-up
// (pipelines, caches) and is not counted as a measurement; the first path is measured on the frames
// after it, and each later frame whose scene differs from the last one's measures a path not yet
// measured, in order. After that the frame takes the path with the lowest measured cost per
// estimated fragment, and each other path is measured again once every kRemeasureEvery changed
// frames times how many times slower it was (remeasure_interval), so the choice follows a scene that
// changes while the frames spent on slower paths stay about 1/kRemeasureEvery of the time: on an
// H200 trace was 6-18x slower than tiles, and a preview would stutter if it took trace every 60
// frames. A frame of the same scene as the last one takes the same path, so repeated renders stay
// identical. A path that refuses a frame (tiles' or ppll's
// budget, a device's loop limit: never a wrong image) is redone at once by the next path, within the
// same frame, and counts as the slowest until it is measured again. The stats say which path was
// taken (the "decide (cpu): ..." pass), and last_choice() names it.
//
// One difference remains for the sorted path: the compositor integrates every sphere, while ppll
// and the reference stop once transmittance falls below the scene's min_transmittance. What lies
// behind such a point contributes at most min_transmittance times its radiance, so auto is exact
// wherever the scene sets min_transmittance = 0 and within that bound otherwise.
#pragma once

#include "render/methods/method.h"
#include "render/methods/ppll.h"
#include "render/methods/cpu_trace_pass.h"
#include "render/methods/sorted.h"
#include "render/methods/tiles.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

namespace brume {

struct AutoOptions {
    PpllOptions ppll;            // the lists for the frames that take ppll (--max-memory reaches them here)
    TilesOptions tiles;          // the tile lists for the frames that take tiles (--max-memory too)
    int threads = 0;             // trace's threads (--threads); 0: all
    bool allow_cpu = true;       // false: intersecting frames never take trace (ppll on a CPU device)
    bool measure_on_cpu = false; // true: measure the paths on a CPU device too (tests, experiments)
};

class AutoMethod : public GpuMethod {
public:
    // Changed frames between two measurements of a path not taken, per time it was slower than the
    // path taken; at most kMaxRemeasureFactor times that (and so for a path that refused).
    static constexpr int kRemeasureEvery = 60;
    static constexpr int kMaxRemeasureFactor = 64;
    // How many changed frames after its measurement a path of cost `cost` is measured again, when the
    // fastest other path costs `best` (ms per fragment; infinite: refused).
    static int remeasure_interval(double cost, double best);

    explicit AutoMethod(vk::Device& device, AutoOptions options = {});
    std::string name() const override { return "auto"; }
    bool exact() const override { return true; }
    // Which path rendered the last frame: "power-sorted", "tiles", "ppll" or "trace".
    std::string last_choice() const { return chosen_->name() == "sorted" ? "power-sorted" : chosen_->name(); }
    const PpllMethod& ppll() const { return ppll_; }
    // The measured cost of a path ("tiles", "ppll", "trace") in ms per estimated fragment; negative
    // until measured, infinite after it refused a frame.
    double measured_cost(const std::string& path) const;

    // The frame path's side: prepare() decides, then every call goes to the method chosen.
    const vk::SharedDescriptors& descriptors() const override { return chosen_->descriptors(); }
    bool has_list_stats() const override { return false; }  // the lists exist only on some frames
    bool uses_opaque_pass() const override { return chosen_->uses_opaque_pass(); }
    bool reads_sphere_sun() const override { return chosen_->reads_sphere_sun(); }
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override { return chosen_->record(cmd, ctx, step); }
    After after_step(FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    enum Path { kTiles = 0, kPpll = 1, kTrace = 2, kPaths = 3 };
    Path choose(bool scene_changed);
    GpuMethod& method_of(Path path);
    // After `path_` refused this frame: makes the next path to try the chosen one, or returns false
    // when none is left.
    bool fall_back();
    // chosen_->prepare(), moving on to the next path while one refuses the scene's budget.
    void prepare_chosen(FrameContext& ctx);
    std::uint64_t fingerprint(const Scene& scene) const;
    // Whether this frame is composited in power-distance order: on a GPU (or without trace), when no
    // two spheres share volume and the light is one the compositor is exact for.
    bool takes_power_sorted(const Scene& scene) const;

    AutoOptions options_;
    PpllMethod ppll_;
    TilesMethod tiles_;
    CpuTracePass trace_;
    SortedCompositor power_sorted_;
    GpuMethod* chosen_;
    double decide_ms_ = 0.0;
    // What the measurements know.
    std::array<double, kPaths> cost_{-1.0, -1.0, -1.0};   // ms per estimated fragment; infinite: refused
    std::array<bool, kPaths> warm_{false, false, false};  // a path's first frame (pipelines compiled) is not a measurement
    std::vector<Path> candidates_;                 // the paths this device may take, the one expected fastest first
    bool cpu_device_ = false;
    Path path_ = kPpll;                            // the last intersecting frame's path
    bool measuring_ = false;                       // this frame's time goes into cost_[path_]
    std::array<bool, kPaths> tried_{};             // the paths this frame tried (a refusal moves on to another)
    int changed_frames_ = 0;                       // intersecting frames whose scene changed
    std::array<int, kPaths> due_{};                // the changed frame from which a path may be measured again
    std::uint64_t last_fingerprint_ = 0;
    double fragments_estimate_ = 0.0;
    std::chrono::steady_clock::time_point frame_start_;
};

}  // namespace brume
