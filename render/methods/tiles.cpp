#include "render/methods/tiles.h"

#include "fullscreen.vert.h"
#include "render/methods/ppll.h"
#include "render/methods/sorted.h"
#include "render/nearest_bounds.h"
#include "render/vk/pipelines.h"
#include "radiance_buffer.frag.h"
#include "tiles_resolve.comp.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace brume {

using namespace vk;

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// An upload buffer of at least `bytes` (Vulkan has no empty buffers), remade when it is too small
// or more than four times too large, and written into the method's set.
void ensure_upload(Buffer& buffer, const Device& device, SharedDescriptors& set, std::uint32_t binding,
                   VkDeviceSize bytes, VkBufferUsageFlags usage, MemoryUse use, const char* name) {
    bytes = std::max<VkDeviceSize>(bytes, 16);
    if (buffer.size() >= bytes && buffer.size() <= 4 * bytes) return;
    buffer = Buffer(device, bytes + bytes / 4, usage, use, name);
    set.write_storage(binding, buffer.get());
}

}  // namespace

TileBudgetError::TileBudgetError(std::uint64_t needed, std::uint64_t allowed)
    : std::runtime_error("the tile lists need " + format_bytes(needed) + " but the budget is " + format_bytes(allowed) +
                         "; raise --max-memory, lower the resolution or the particle count") {}

TilesMethod::TilesMethod(Device& device, TilesOptions options) : GpuMethod(device), options_(options) {
    counters_ = Buffer(device, sizeof(gpu::ListCounters),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                           VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       MemoryUse::Device, "tiles.counters");
    counters_readback_ = Buffer(device, sizeof(gpu::ListCounters), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                MemoryUse::Readback, "tiles.counters_readback");
    descriptors_.write_storage(gpu::BINDING_COUNTERS, counters_.get());
    max_bytes_ = options.max_bytes ? options.max_bytes : device.device_local_bytes() / 2;
}

void TilesMethod::ensure_pipelines(bool accurate) {
    if (pipelines_made_ && accurate == pipeline_accurate_) return;
    // Specialization constant 3: the accurate shadow technique (exact_integrator.glsl); 0..2 unused.
    resolve_pipeline_ = create_compute_pipeline(device_, descriptors_.pipeline_layout(), "tiles_resolve",
                                                BRUME_SPIRV(spv_tiles_resolve_comp), {0u, 0u, 0u, accurate ? 1u : 0u});
    if (!pipelines_made_) {
        GraphicsPipelineDesc composite;
        composite.name = "tiles_composite";
        composite.vertex = BRUME_SPIRV(spv_fullscreen_vert);
        composite.fragment = BRUME_SPIRV(spv_radiance_buffer_frag);
        composite.color_formats = {FrameResources::kHdrFormat};
        composite_pipeline_ = create_graphics_pipeline(device_, descriptors_.pipeline_layout(), composite);
    }
    pipelines_made_ = true;
    pipeline_accurate_ = accurate;
}

void TilesMethod::upload_bins(VkExtent2D extent) {
    const std::uint64_t entry_bytes = bins_.entries.size() * sizeof(std::uint32_t);
    const std::uint64_t first_bytes = bins_.first.size() * sizeof(std::uint32_t);
    const std::uint64_t result_bytes = std::uint64_t(extent.width) * extent.height * 16;
    const std::uint64_t needed = entry_bytes + first_bytes + result_bytes;
    if (needed > max_bytes_) throw TileBudgetError(needed, max_bytes_);
    const VkDeviceSize range = device_.properties().limits.maxStorageBufferRange;
    if (entry_bytes > range || result_bytes > range)
        throw TileBudgetError(std::max(entry_bytes, result_bytes), range);
    ensure_upload(first_buffer_, device_, descriptors_, gpu::BINDING_TILE_FIRST, first_bytes,
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "tiles.first");
    ensure_upload(entry_buffer_, device_, descriptors_, gpu::BINDING_TILE_ENTRIES, entry_bytes,
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "tiles.entries");
    if (result_buffer_.size() != result_bytes) {
        result_buffer_ = Buffer(device_, result_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, "tiles.result");
        descriptors_.write_storage(gpu::BINDING_RADIANCE_BUFFER, result_buffer_.get());
    }
    std::memcpy(first_buffer_.mapped(), bins_.first.data(), first_bytes);
    std::memcpy(entry_buffer_.mapped(), bins_.entries.data(), entry_bytes);
}

void TilesMethod::prepare(FrameContext& ctx) {
    const Scene& scene = ctx.scene();
    const bool accurate = scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::Accurate;
    ensure_pipelines(accurate);
    if (accurate) ctx.need_sun_depth_map();
    auto start = std::chrono::steady_clock::now();
    nearest_event_bounds(scene, bound_);
    sort_back_to_front(order_, bound_);  // far to near, from last frame's order: about linear in an animation
    near_to_far_.assign(order_.rbegin(), order_.rend());
    sort_ms_ = ms_since(start);
    start = std::chrono::steady_clock::now();
    const VkExtent2D extent = ctx.extent();
    // The frame path may render larger than the camera says (supersampling): bin for the target, on
    // every core (at 1,000,000 spheres on an H200's host one core took 82 ms, the GPU's resolve 12).
    bin_spheres(scene, int(extent.width), int(extent.height), gpu::TILE_SIZE, near_to_far_, bound_, bins_);
    bin_ms_ = ms_since(start);
    upload_bins(extent);
    const std::uint32_t flags = ctx.list_stats_wanted() ? gpu::FRAME_COLLECT_LIST_STATS : 0u;
    // z: the iterations of the resolve's closing probe loop (shaders/tiles_resolve.comp).
    ctx.uniforms().pool = gpu::uvec4(bins_.tiles_x, bins_.tiles_y, 2u, flags);
}

bool TilesMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    vkCmdFillBuffer(cmd, counters_.get(), 0, VK_WHOLE_SIZE, 0);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    // The opaque pass's radiance and distance, read as a storage image.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_pipeline_.get());
    ctx.bind_compute(cmd);
    vkCmdDispatch(cmd, bins_.tiles_x, bins_.tiles_y, 1);
    ctx.mark(cmd, "resolve");
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
    ctx.resolve_to_hdr(cmd, composite_pipeline_.get());
    ctx.mark(cmd, "composite");
    VkBufferCopy copy{0, 0, sizeof(gpu::ListCounters)};
    vkCmdCopyBuffer(cmd, counters_.get(), counters_readback_.get(), 1, &copy);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
    return true;
}

GpuMethod::After TilesMethod::after_step(FrameContext&, int) {
    std::memcpy(&counters_seen_, counters_readback_.mapped(), sizeof counters_seen_);
    if (counters_seen_.unresolved > 0) throw ListResolveError(counters_seen_.unresolved, bins_.longest, true);
    return After::Done;
}

void TilesMethod::report(FrameStats& stats, const FrameContext& ctx) {
    const gpu::ListCounters& counters = counters_seen_;
    // The sort and the binning run on the CPU; listed with the GPU passes because every frame pays.
    stats.passes.insert(stats.passes.begin(), {"bin (cpu)", bin_ms_});
    stats.passes.insert(stats.passes.begin(), {"sort (cpu)", sort_ms_});
    stats.fragments = counters.allocated;
    stats.pool_capacity = bins_.entry_count();
    stats.pool_bytes = bins_.entries.size() * sizeof(std::uint32_t);
    stats.memory_bytes = stats.pool_bytes + first_buffer_.size() + result_buffer_.size() + counters_.size();
    stats.list_stats = ctx.list_stats_wanted();
    stats.max_list_length = counters.max_length;
    stats.nonempty_pixels = counters.nonempty_pixels;
    stats.mean_list_length = counters.nonempty_pixels ? double(counters.allocated) / counters.nonempty_pixels : 0.0;
    stats.long_list_pixels = counters.long_lists;
}

}  // namespace brume
