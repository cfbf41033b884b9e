// The `sorted` method (the painter's algorithm users have today, as in the WebGL lesson "11.4
// Transparency (and Alpha Blending)") and the machinery it shares with `soft`: spheres sorted back to
// front by the view depth of their centres, on the CPU, with an insertion sort that starts from last
// frame's order, then composited with premultiplied "over" blending into the HDR target, which is
// first filled with the opaque image's radiance.
// `sorted` draws one classic camera-facing planar billboard per sphere, with the sphere's whole
// chord and a hard depth cut where the plane meets geometry. Exact only where spheres lie wholly in
// front of the eye and the opaque surface with disjoint depth ranges; it pops whenever two
// particles' centre depths cross. The billboard in detail: docs/methods.md, sorted.
#pragma once

#include "render/frame/gpu_method.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brume {

// Depth of each sphere centre along the view direction, dot(centre - eye, forward): the sort key.
std::vector<double> view_depths(const Scene& scene);

// Work done by one sort_back_to_front call.
struct SortCounts {
    std::uint64_t comparisons = 0;  // by the insertion sort
    std::uint64_t moves = 0;        // elements shifted by one place: the inversions it removed
    bool full_sort = false;         // the order was far from sorted: finished by std::stable_sort
};

// Turns `order`, last frame's back-to-front permutation of sphere indices, into this frame's, for the
// spheres 0 .. depth.size() - 1 (identity is the sphere index). Indices no longer present are
// dropped, new ones are appended at the front end (nearest) before sorting, and anything that is not
// a permutation is repaired the same way. Then a stable insertion sort by decreasing depth: its cost
// is n - 1 comparisons plus one per inversion, so a coherent animation sorts in about linear time,
// and spheres at equal depth keep last frame's order. Past 32 n + 1024 moves (a first frame, a burst
// of new particles) it finishes with std::stable_sort instead, with the same result, so no frame
// costs O(n^2).
SortCounts sort_back_to_front(std::vector<std::uint32_t>& order, const std::vector<double>& depth);

// What `sorted`, `soft` and auto's power-sorted path share: the CPU sort and its order buffer, the
// opaque copy and the blended billboard pass. They differ only in their billboard shaders and key.
class SortedCompositor : public GpuMethod {
public:
    enum class Billboard {
        Planar,     // sorted: camera-facing plane through the centre, whole chord, hard depth cut
        Spherical,  // soft: the exact chord clipped by the eye and the opaque surface (sphere_sample.glsl)
    };
    enum class SortKey {
        CentreDepth,    // dot(centre - eye, forward): the painter's classic key
        PowerDistance,  // |centre - eye|^2 - radius^2: exact order for spheres that do not intersect
    };
    SortedCompositor(vk::Device& device, Billboard billboard, SortKey key = SortKey::CentreDepth);

    // "sorted" (planar), "soft" (spherical) or "power-sorted" (spherical, power distance).
    std::string name() const override;
    bool exact() const override { return false; }  // power-sorted is exact only without intersections

    // This frame's back-to-front order (sphere indices) and the work its sort took.
    const std::vector<std::uint32_t>& order() const { return order_; }
    const SortCounts& last_sort() const { return last_sort_; }

    // The frame path's side (render/frame/gpu_method.h). prepare() sorts, reusing the previous
    // order: consecutive frames are taken to be consecutive frames of one animation.
    void prepare(FrameContext& ctx) override;
    bool record(VkCommandBuffer cmd, FrameContext& ctx, int step) override;
    void report(FrameStats& stats, const FrameContext& ctx) override;

private:
    void ensure_order_buffer(std::size_t spheres);

    Billboard billboard_;
    SortKey key_;
    vk::UniquePipeline copy_pipeline_;
    vk::UniquePipeline billboard_pipeline_;
    vk::Buffer order_buffer_;  // uint[]: draw i shows sphere order_buffer_[i]
    std::vector<std::uint32_t> order_;
    std::vector<double> depth_;
    SortCounts last_sort_;
    double sort_ms_ = 0.0;
};

// Consecutive render() calls are consecutive frames: each sort starts from the previous call's order.
class SortedMethod : public SortedCompositor {
public:
    explicit SortedMethod(vk::Device& device) : SortedCompositor(device, Billboard::Planar) {}
};

// `--method sorted`; it takes no setting (throws std::invalid_argument on one).
std::unique_ptr<Method> make_sorted_method(vk::Device& device, const std::string& setting);

}  // namespace brume
