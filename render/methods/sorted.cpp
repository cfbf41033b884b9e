#include "render/methods/sorted.h"

#include "fullscreen_ray.vert.h"
#include "render/vk/pipelines.h"
#include "sim/camera_rays.h"
#include "soft_particle.frag.h"
#include "soft_particle.vert.h"
#include "sorted_billboard.frag.h"
#include "sorted_billboard.vert.h"
#include "sorted_opaque_copy.frag.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace brume {

using namespace vk;

std::vector<double> view_depths(const Scene& scene) {
    const CameraRays rays = make_camera_rays(scene.camera);
    std::vector<double> depth(scene.spheres.size());
    for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = glm::dot(scene.spheres[i].center - rays.eye, rays.forward);
    return depth;
}

SortCounts sort_back_to_front(std::vector<std::uint32_t>& order, const std::vector<double>& depth) {
    const std::size_t n = depth.size();
    // Carry last frame's order over: keep the indices that still exist, once each, in their old
    // places; append the new ones at the near end, where emitters usually put young particles.
    std::vector<bool> seen(n, false);
    std::size_t kept = 0;
    for (const std::uint32_t index : order) {
        if (index >= n || seen[index]) continue;
        seen[index] = true;
        order[kept++] = index;
    }
    order.resize(kept);
    for (std::uint32_t index = 0; index < n; ++index)
        if (!seen[index]) order.push_back(index);

    // Stable insertion sort, farthest first: n - 1 comparisons plus one per inversion. An order far
    // from sorted (the first frame, a burst of new particles) would cost O(n^2): past a budget of
    // moves the rest is left to std::stable_sort, which gives the same result (insertion sort never
    // reorders equal keys, so equal keys are still in last frame's order when it takes over).
    SortCounts counts;
    const std::uint64_t budget = 32 * std::uint64_t(n) + 1024;
    for (std::size_t i = 1; i < n; ++i) {
        const std::uint32_t index = order[i];
        const double d = depth[index];
        std::size_t j = i;
        while (j > 0) {
            ++counts.comparisons;
            if (!(depth[order[j - 1]] < d)) break;
            order[j] = order[j - 1];
            ++counts.moves;
            --j;
        }
        order[j] = index;
        if (counts.moves > budget) {
            std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return depth[a] > depth[b]; });
            counts.full_sort = true;
            break;
        }
    }
    return counts;
}

SortedCompositor::SortedCompositor(Device& device, Billboard billboard, SortKey key)
    : GpuMethod(device), billboard_(billboard), key_(key) {
    const bool planar = billboard == Billboard::Planar;
    GraphicsPipelineDesc copy;
    copy.name = planar ? "sorted_opaque_copy" : "soft_opaque_copy";
    copy.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    copy.fragment = BRUME_SPIRV(spv_sorted_opaque_copy_frag);
    copy.color_formats = {FrameResources::kHdrFormat};
    copy_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), copy);

    GraphicsPipelineDesc particles;
    particles.name = planar ? "sorted_billboard" : "soft_particle";
    particles.vertex = planar ? BRUME_SPIRV(spv_sorted_billboard_vert) : BRUME_SPIRV(spv_soft_particle_vert);
    particles.fragment = planar ? BRUME_SPIRV(spv_sorted_billboard_frag) : BRUME_SPIRV(spv_soft_particle_frag);
    particles.color_formats = {FrameResources::kHdrFormat};
    particles.blends = {blend_premultiplied_over()};
    billboard_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), particles);
    ensure_order_buffer(1);
}

std::string SortedCompositor::name() const {
    if (billboard_ == Billboard::Planar) return "sorted";
    return key_ == SortKey::PowerDistance ? "power-sorted" : "soft";
}

void SortedCompositor::ensure_order_buffer(std::size_t spheres) {
    // At least one element (Vulkan has no empty buffers); shrink only when far too large.
    const VkDeviceSize bytes = std::max<std::size_t>(spheres, 1) * sizeof(std::uint32_t);
    if (order_buffer_.size() >= bytes && order_buffer_.size() <= 4 * bytes) return;
    order_buffer_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload,
                           billboard_ == Billboard::Planar ? "sorted.order" : "soft.order");
    descriptors_.write_storage(gpu::BINDING_SORT_ORDER, order_buffer_.get());
}

void SortedCompositor::prepare(FrameContext& ctx) {
    const Scene& scene = ctx.scene();
    const auto sort_start = std::chrono::steady_clock::now();
    if (key_ == SortKey::CentreDepth) {
        depth_ = view_depths(scene);
    } else {
        depth_.resize(scene.spheres.size());
        for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
            const glm::dvec3 d = scene.spheres[k].center - scene.camera.position;
            depth_[k] = glm::dot(d, d) - scene.spheres[k].radius * scene.spheres[k].radius;
        }
    }
    last_sort_ = sort_back_to_front(order_, depth_);
    sort_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sort_start).count();

    ensure_order_buffer(order_.size());
    if (!order_.empty()) std::memcpy(order_buffer_.mapped(), order_.data(), order_.size() * sizeof(std::uint32_t));
}

bool SortedCompositor::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    // One rendering: the opaque radiance first, then every billboard blended over it in draw order,
    // which the rasteriser keeps per pixel (primitive order), so the sort is the compositing order.
    // (One pass in the statistics: a timestamp between the two draws reads wrong on lavapipe, which
    // bins the whole rendering before it rasterises any of it.)
    ctx.begin_hdr_rendering(cmd);
    ctx.bind(cmd);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, copy_pipeline_);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    if (ctx.sphere_count() > 0) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, billboard_pipeline_);
        vkCmdDraw(cmd, 6, ctx.sphere_count(), 0, 0);
    }
    ctx.end_hdr_rendering(cmd);
    ctx.mark(cmd, "composite");
    return true;
}

void SortedCompositor::report(FrameStats& stats, const FrameContext&) {
    // The sort runs on the CPU; it is listed with the GPU passes because every frame pays for it.
    stats.passes.insert(stats.passes.begin(), {"sort (cpu)", sort_ms_});
    stats.memory_bytes = order_buffer_.size();
}

std::unique_ptr<Method> make_sorted_method(Device& device, const std::string& setting) {
    if (!setting.empty()) throw std::invalid_argument("method 'sorted' takes no setting (got ':" + setting + "')");
    return std::make_unique<SortedMethod>(device);
}

}  // namespace brume
