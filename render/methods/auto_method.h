// `auto`: model no more than the frame needs, and take the fastest exact path on this device.
//
// When no two spheres on screen share volume, compositing whole spheres back to front in
// power-distance order (|c - eye|^2 - r^2) is exact, with each sphere's chord clipped by the eye and
// the opaque surface, and needs no per-pixel lists. The choice is made per frame on the CPU
// (sim/sphere_overlap.h, O(n log n); why: docs/decisions.md, "`auto` decides per frame on the CPU").
//
// Frames with intersecting spheres take the fastest exact path measured on this device: ppll, or
// `trace`, the float CPU tracer (render/fast_tracer.h; on a CPU device such as lavapipe it is the
// faster by far: docs/performance.md, "trace"). On a CPU device trace is taken without measuring
// (it was the faster at every size and scene measured there, and an image should not depend on the
// machine's load); elsewhere the paths are measured. The first measured frame takes the path expected
// to be faster, trace on a CPU device and ppll on a GPU; a path's first frame is a warm-up (pipelines,
// caches) and is not counted as a measurement. Each later frame whose scene differs from the last
// one's may try a path not yet measured; after that the frame takes the path with the lowest
// measured cost per estimated fragment, and every kRemeasureEvery changed frames the other path is
// measured again, so the choice follows a scene that changes. A frame of the same scene as the last
// one takes the same path, so repeated renders stay identical. The stats say which path was taken
// (the "decide (cpu): ..." pass), and last_choice() names it.
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

#include <array>
#include <chrono>
#include <cstdint>

namespace brume {

struct AutoOptions {
    PpllOptions ppll;            // the lists for the frames that take ppll (--max-memory reaches them here)
    int threads = 0;             // trace's threads (--threads); 0: all
    bool allow_cpu = true;       // false: intersecting frames always take ppll
    bool measure_on_cpu = false; // true: measure the two paths on a CPU device too (tests, experiments)
};

class AutoMethod : public GpuMethod {
public:
    // Changed frames between two measurements of the path not taken.
    static constexpr int kRemeasureEvery = 60;

    explicit AutoMethod(vk::Device& device, AutoOptions options = {});
    std::string name() const override { return "auto"; }
    bool exact() const override { return true; }
    // Which path rendered the last frame: "power-sorted", "ppll" or "trace".
    std::string last_choice() const { return chosen_->name() == "sorted" ? "power-sorted" : chosen_->name(); }
    const PpllMethod& ppll() const { return ppll_; }
    // The measured cost of a path in ms per estimated fragment; negative until measured.
    double measured_cost(const std::string& path) const;

    // The frame path's side: prepare() decides, then every call goes to the method chosen.
    const vk::SharedDescriptors& descriptors() const override { return chosen_->descriptors(); }
    bool has_list_stats() const override { return false; }  // the lists exist only on some frames
    bool uses_opaque_pass() const override { return chosen_->uses_opaque_pass(); }
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override { return chosen_->record(cmd, ctx, step); }
    After after_step(FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    enum Path { kPpll = 0, kTrace = 1, kPaths = 2 };
    Path choose(bool scene_changed);
    std::uint64_t fingerprint(const Scene& scene) const;

    AutoOptions options_;
    PpllMethod ppll_;
    CpuTracePass trace_;
    SortedCompositor power_sorted_;
    GpuMethod* chosen_;
    double decide_ms_ = 0.0;
    // What the measurements know.
    std::array<double, kPaths> cost_{-1.0, -1.0};  // ms per estimated fragment
    std::array<bool, kPaths> warm_{false, false};  // a path's first frame (pipelines compiled) is not a measurement
    bool cpu_device_ = false;
    Path first_ = kPpll;                           // the path measured first: the one expected to be faster
    Path path_ = kPpll;                            // the last intersecting frame's path
    bool measuring_ = false;                       // this frame's time goes into cost_[path_]
    int changed_frames_ = 0;                       // intersecting frames whose scene changed
    std::uint64_t last_fingerprint_ = 0;
    double fragments_estimate_ = 0.0;
    std::chrono::steady_clock::time_point frame_start_;
};

}  // namespace brume
