#include "render/methods/ppll.h"

#include "render/frame/frame_path.h"

#include "fullscreen_ray.vert.h"
#include "ppll_append.frag.h"
#include "ppll_resolve.frag.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"
#include "sphere_impostor_ordered.vert.h"
#include "render/nearest_bounds.h"
#include "render/methods/sorted.h"
#include "sim/camera_rays.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace brume {

using namespace vk;

namespace {

std::uint64_t nodes_bytes(std::uint64_t nodes) { return nodes * gpu::NODE_BYTES; }

// The interval of tangent slopes of a circle seen from the origin (see shaders/screen_bounds.glsl).
void tangent_slopes(double lateral, double depth, double r, double& lo, double& hi) {
    const double denom = depth * depth - r * r;
    const double root = r * std::sqrt(std::max(lateral * lateral + denom, 0.0));
    lo = (lateral * depth - root) / denom;
    hi = (lateral * depth + root) / denom;
}

}  // namespace

ListResolveError::ListResolveError(std::uint64_t pixels, std::uint32_t longest, bool tiles)
    : std::runtime_error(std::to_string(pixels) + (pixels == 1 ? " pixel" : " pixels") +
                         " could not be resolved on this device: " +
                         (tiles         ? "the fullest tile lists " + std::to_string(longest) + " spheres"
                          : longest > 0 ? "the longest list has " + std::to_string(longest) + " nodes of overlapping media"
                                        : "its lists of overlapping media are too long") +  // lengths not gathered
                         ", and the device cut the resolve's loops short (lavapipe ends a shader's loops after 65,535 "
                         "iterations in all); no image was written. Use --method trace (exact, on the CPU, with no "
                         "loop limit), or fewer overlapping particles") {}

PoolBudgetError::PoolBudgetError(std::uint64_t needed, std::uint64_t allowed, bool addressable)
    : std::runtime_error(
          "the per-pixel lists need " + format_bytes(needed) + " of node pool but " +
          (addressable ? "the " + std::to_string(gpu::MAX_POOL_PARTS) + " pool parts this device can address hold " +
                             format_bytes(allowed) + "; lower the resolution or the particle count"
                       : "the budget holds " + format_bytes(allowed) + " of whole " +
                             std::to_string(gpu::NODE_BYTES) +
                             "-byte nodes; raise --max-memory, lower the resolution or the particle count")),
      needed_(needed),
      allowed_(allowed) {}

std::uint64_t estimate_fragments(const Scene& scene) {
    const CameraRays rays = make_camera_rays(scene.camera);
    const double w = scene.camera.width, h = scene.camera.height;
    const double sx = glm::length(rays.right), sy = glm::length(rays.up);
    const glm::dvec3 right = rays.right / sx, up = rays.up / sy;
    double total = 0.0;
    for (const Sphere& s : scene.spheres) {
        if (!(s.extinction > 0.0)) continue;
        const glm::dvec3 v = s.center - rays.eye;
        const double depth = glm::dot(v, rays.forward);
        if (depth < -s.radius) continue;
        if (depth <= s.radius * 1.001) {
            total += w * h;
            continue;
        }
        double x0, x1, y0, y1;
        tangent_slopes(glm::dot(v, right), depth, s.radius, x0, x1);
        tangent_slopes(glm::dot(v, up), depth, s.radius, y0, y1);
        // Pixels of the (clipped) bounding rectangle, times pi/4 for the ellipse inside it.
        const double px0 = std::clamp((x0 / sx + 1.0) * 0.5 * w, 0.0, w), px1 = std::clamp((x1 / sx + 1.0) * 0.5 * w, 0.0, w);
        const double py0 = std::clamp((y0 / sy + 1.0) * 0.5 * h, 0.0, h), py1 = std::clamp((y1 / sy + 1.0) * 0.5 * h, 0.0, h);
        total += (px1 - px0) * (py1 - py0) * 0.785398;
    }
    return std::uint64_t(total);
}

PpllMethod::PpllMethod(Device& device, PpllOptions options) : GpuMethod(device), options_(options) {
    counters_ = Buffer(device, sizeof(gpu::ListCounters),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                           VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       MemoryUse::Device, "ppll.counters");
    counters_readback_ = Buffer(device, sizeof(gpu::ListCounters), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                MemoryUse::Readback, "ppll.counters_readback");
    descriptors_.write_storage(gpu::BINDING_COUNTERS, counters_.get());

    // Pool parts are the largest power of two of nodes one storage-buffer descriptor can address.
    const std::uint64_t range = device.properties().limits.maxStorageBufferRange;
    part_shift_ = 0;
    while (part_shift_ < 28 && nodes_bytes(2ull << part_shift_) <= range) ++part_shift_;
    if (options.part_nodes) {
        if (options.part_nodes & (options.part_nodes - 1))
            throw std::invalid_argument("PpllOptions::part_nodes must be a power of two");
        while ((1ull << part_shift_) > options.part_nodes) --part_shift_;
    }
    const std::uint64_t addressable = std::uint64_t(gpu::MAX_POOL_PARTS) << part_shift_;
    max_pool_bytes_ = options.max_pool_bytes ? options.max_pool_bytes : device.device_local_bytes() / 2;
    max_nodes_ = std::min(addressable, max_pool_bytes_ / gpu::NODE_BYTES);
}

void PpllMethod::ensure_pipelines(std::uint32_t parts, bool accurate) {
    if (parts == pipeline_parts_ && accurate == pipeline_accurate_) return;
    // Specialization constants: 1, pool parts (see ppll_storage.glsl); 2, the resolve's ordered
    // path (ppll_resolve.frag); 3, the accurate shadow technique (exact_integrator.glsl); 0 is unused.
    const std::vector<std::uint32_t> constants = {0u, parts, options_.ordered_path ? 1u : 0u, accurate ? 1u : 0u};
    GraphicsPipelineDesc append;
    append.name = "ppll_append";
    append.vertex = BRUME_SPIRV(spv_sphere_impostor_ordered_vert);
    append.fragment = BRUME_SPIRV(spv_ppll_append_frag);
    append.fragment_constants = constants;
    append_pipeline_ = create_graphics_pipeline(device_, descriptors_.pipeline_layout(), append);

    GraphicsPipelineDesc resolve;
    resolve.name = "ppll_resolve";
    resolve.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    resolve.fragment = BRUME_SPIRV(spv_ppll_resolve_frag);
    resolve.color_formats = {FrameResources::kHdrFormat};
    resolve.fragment_constants = constants;
    resolve_pipeline_ = create_graphics_pipeline(device_, descriptors_.pipeline_layout(), resolve);
    pipeline_parts_ = parts;
    pipeline_accurate_ = accurate;
}

void PpllMethod::ensure_heads(VkExtent2D extent) {
    const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * sizeof(std::uint32_t);
    if (heads_.size() == bytes) return;
    if (bytes > device_.properties().limits.maxStorageBufferRange)
        throw std::runtime_error("resolution " + std::to_string(extent.width) + "x" + std::to_string(extent.height) +
                                 " needs a " + format_bytes(bytes) + " head-pointer buffer, more than this device's " +
                                 format_bytes(device_.properties().limits.maxStorageBufferRange) + " storage-buffer limit");
    heads_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                    MemoryUse::Device, "ppll.heads");
    descriptors_.write_storage(gpu::BINDING_HEADS, heads_.get());
}

void PpllMethod::allocate_pool(std::uint64_t nodes) {
    // A small floor saves regrowing for trivial scenes, but never beyond the budget.
    nodes = std::min(std::max<std::uint64_t>(nodes, 1024), std::max<std::uint64_t>(max_nodes_, 1));
    pool_parts_.clear();  // free the old pool before allocating the new one
    const std::uint64_t per_part = 1ull << part_shift_;
    std::vector<VkBuffer> handles;
    for (std::uint64_t first = 0; first < nodes; first += per_part) {
        const std::uint64_t count = std::min(per_part, nodes - first);
        pool_parts_.emplace_back(device_, nodes_bytes(count), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device,
                                 "ppll.pool[" + std::to_string(pool_parts_.size()) + "]");
        handles.push_back(pool_parts_.back().get());
    }
    // Unused slots repeat part 0: the shaders never index past the parts that exist.
    while (handles.size() < gpu::MAX_POOL_PARTS) handles.push_back(handles.front());
    descriptors_.write_storage_array(gpu::BINDING_POOL, handles);
    capacity_ = nodes;
    ensure_pipelines(std::uint32_t(pool_parts_.size()), pipeline_accurate_);
}

void PpllMethod::write_pool_uniforms(FrameContext& ctx) const {
    const std::uint32_t flags = ctx.list_stats_wanted() ? gpu::FRAME_COLLECT_LIST_STATS : 0u;
    ctx.uniforms().pool = gpu::uvec4(std::uint32_t(capacity_), part_shift_, std::uint32_t(pool_parts_.size()), flags);
}

void PpllMethod::upload_draw_order(const Scene& scene) {
    const auto start = std::chrono::steady_clock::now();
    nearest_event_bounds(scene, bound_);
    // Far to near, starting from last frame's order (an animation sorts in about linear time).
    sort_back_to_front(order_, bound_);
    const std::size_t n = std::max<std::size_t>(order_.size(), 1);  // Vulkan has no empty buffers
    if (order_buffer_.size() < n * sizeof(std::uint32_t) || order_buffer_.size() > 4 * n * sizeof(std::uint32_t)) {
        order_buffer_ = Buffer(device_, n * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload,
                               "ppll.draw_order");
        bound_buffer_ = Buffer(device_, n * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload,
                               "ppll.bounds");
        descriptors_.write_storage(gpu::BINDING_SORT_ORDER, order_buffer_.get());
        descriptors_.write_storage(gpu::BINDING_PPLL_BOUNDS, bound_buffer_.get());
    }
    if (!order_.empty()) std::memcpy(order_buffer_.mapped(), order_.data(), order_.size() * sizeof(std::uint32_t));
    float* bounds = bound_buffer_.as<float>();
    for (std::size_t k = 0; k < bound_.size(); ++k) bounds[k] = float(bound_[k]);  // rounds by < the margin
    sort_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void PpllMethod::prepare(FrameContext& ctx) {
    ensure_heads(ctx.extent());
    const Scene& scene = ctx.scene();
    const bool accurate = scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::Accurate;
    if (capacity_ > 0) ensure_pipelines(std::uint32_t(pool_parts_.size()), accurate);
    else pipeline_accurate_ = accurate;  // allocate_pool below makes the pipelines
    if (accurate) ctx.need_sun_depth_map();
    upload_draw_order(ctx.scene());
    if (capacity_ == 0) {
        std::uint64_t want = options_.initial_nodes;
        if (want == 0) {
            const std::uint64_t estimate = estimate_fragments(ctx.scene());
            want = estimate + estimate / 4;
        }
        allocate_pool(std::min(want, max_nodes_));
    }
    write_pool_uniforms(ctx);
}

bool PpllMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    // Empty lists and zeroed counters, ordered before the fragment shaders' atomics.
    vkCmdFillBuffer(cmd, heads_.get(), 0, VK_WHOLE_SIZE, gpu::LIST_END);
    vkCmdFillBuffer(cmd, counters_.get(), 0, VK_WHOLE_SIZE, 0);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

    // Particle pass: no attachments, the fragment shader only appends to the lists.
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, ctx.extent()};
    info.layerCount = 1;
    vkCmdBeginRendering(cmd, &info);
    ctx.draw_spheres(cmd, append_pipeline_);
    vkCmdEndRendering(cmd);
    ctx.mark(cmd, "particles");
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

    ctx.resolve_to_hdr(cmd, resolve_pipeline_);
    ctx.mark(cmd, "resolve");

    memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy copy{0, 0, sizeof(gpu::ListCounters)};
    vkCmdCopyBuffer(cmd, counters_.get(), counters_readback_.get(), 1, &copy);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
    return true;
}

GpuMethod::After PpllMethod::after_step(FrameContext& ctx, int) {
    std::memcpy(&counters_seen_, counters_readback_.mapped(), sizeof counters_seen_);
    if (counters_seen_.allocated <= capacity_) {
        if (counters_seen_.unresolved > 0) throw ListResolveError(counters_seen_.unresolved, counters_seen_.max_length);
        return After::Done;
    }
    // Overflow: nothing past capacity was written and the frame is discarded. Grow to what this
    // frame needed plus headroom for the next one, and render again.
    const std::uint64_t needed = counters_seen_.allocated;
    if (needed > max_nodes_)
        throw PoolBudgetError(nodes_bytes(needed), nodes_bytes(max_nodes_), max_nodes_ < max_pool_bytes_ / gpu::NODE_BYTES);
    allocate_pool(std::min(max_nodes_, needed + needed / 4));
    write_pool_uniforms(ctx);
    return After::Again;
}

void PpllMethod::report(FrameStats& stats, const FrameContext& ctx) {
    const gpu::ListCounters& counters = counters_seen_;
    // The sort runs on the CPU; it is listed with the GPU passes because every frame pays for it.
    stats.passes.insert(stats.passes.begin(), {"sort (cpu)", sort_ms_});
    stats.fragments = counters.allocated;
    stats.pool_capacity = capacity_;
    stats.pool_bytes = nodes_bytes(capacity_);
    stats.memory_bytes = stats.pool_bytes + heads_.size() + counters_.size() + order_buffer_.size() + bound_buffer_.size();
    stats.list_stats = ctx.list_stats_wanted();
    stats.max_list_length = counters.max_length;
    stats.nonempty_pixels = counters.nonempty_pixels;
    stats.mean_list_length = counters.nonempty_pixels ? double(counters.allocated) / counters.nonempty_pixels : 0.0;
    stats.long_list_pixels = counters.long_lists;
}

Image PpllMethod::render(const Scene& scene, FrameStats* stats, bool list_stats) {
    return own_path().render(*this, scene, stats, list_stats);
}

}  // namespace brume
