#include "render/frame/frame_resources.h"

#include "opaque_boxes.frag.h"
#include "opaque_boxes.vert.h"
#include "render/sun_depth_map.h"
#include "render/sun_light.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"

#include <glm/geometric.hpp>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace brume {

using namespace vk;

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

FrameResources::FrameResources(const Device& device) : device_(device), descriptors_(device) {
    GraphicsPipelineDesc desc;
    desc.name = "opaque_boxes";
    desc.vertex = BRUME_SPIRV(spv_opaque_boxes_vert);
    desc.fragment = BRUME_SPIRV(spv_opaque_boxes_frag);
    desc.color_formats = {kOpaqueFormat};
    desc.depth_format = kDepthFormat;
    desc.depth_compare = VK_COMPARE_OP_GREATER;  // depth = 1/(1+t): nearer is larger
    opaque_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), desc);
    if (SunMapPass::wanted_on(device)) sun_map_pass_.emplace(device, descriptors_);
    uniform_buffer_ = Buffer(device, sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                             MemoryUse::Upload, "frame.uniforms");
}

void FrameResources::write_frame_bindings(const SharedDescriptors& descriptors) const {
    descriptors.write_uniform(gpu::BINDING_FRAME, uniform_buffer_.get());
    descriptors.write_storage(gpu::BINDING_SPHERES, sphere_buffer_.get());
    descriptors.write_storage(gpu::BINDING_BOXES, box_buffer_.get());
    descriptors.write_storage(gpu::BINDING_SUN_GRID, sun_grid_buffer_.get());
    descriptors.write_storage_image(gpu::BINDING_OPAQUE, opaque_image_.view());
}

void FrameResources::upload(const Scene& scene) {
    if (!scene.volumes.empty())
        throw std::logic_error("the scene's [[vdb]] volumes were not converted to spheres "
                               "(sim/vdb/volume_loader.h convert_scene_volumes)");
    const VkExtent2D extent{std::uint32_t(scene.camera.width), std::uint32_t(scene.camera.height)};
    const VkDeviceSize sphere_bytes = std::max<std::size_t>(scene.spheres.size(), 1) * sizeof(gpu::GpuSphere);
    const VkDeviceSize box_bytes = std::max<std::size_t>(scene.boxes.size(), 1) * sizeof(gpu::GpuBox);
    const bool resize = extent.width != extent_.width || extent.height != extent_.height;
    const bool new_spheres = sphere_buffer_.size() < sphere_bytes || sphere_buffer_.size() > 4 * sphere_bytes;
    const bool new_boxes = box_buffer_.size() < box_bytes;
    // The sun (render/sun_light.h). Its light-space grid waits for a reader: the per-sphere T_sun
    // (ensure_sphere_sun) on the CPU, the opaque pass's exact T_sun at lit box hits through its GPU
    // copy (ensure_sun_grid). A CPU tracer's frame reads neither.
    sun_light_ = std::make_unique<SunLight>(scene);
    light_prep_ = LightPrepTimes{};
    eye_ = scene.camera.position;  // every position goes to the device relative to it (gpu_types.h)
    // Room for the depth map the previous frame had (and its columns), so that an animation does not
    // regrow every frame, nor a scene with columns shrink the buffer to its grid and grow it again.
    if (sun_header_.map_size.x > 0) map_words_room_ = sun_map_words_;
    const bool new_grid = sun_grid_buffer_.size() == 0;
    // Only a presenter's passes of the previous frame can still be running here (the frame path waits
    // for every method pass before it returns), and they read the HDR target alone: host writes are
    // safe, but objects about to be destroyed must wait for them.
    if (resize || new_spheres || new_boxes || new_grid) {
        device_.wait_idle();
    }
    if (resize) {
        const VkImageUsageFlags storage_target = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
        opaque_image_ = DeviceImage(device_, kOpaqueFormat, extent, storage_target, VK_IMAGE_ASPECT_COLOR_BIT, "frame.opaque");
        depth_image_ = DeviceImage(device_, kDepthFormat, extent, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                             VK_IMAGE_ASPECT_DEPTH_BIT, "frame.depth");
        hdr_image_ = DeviceImage(device_, kHdrFormat, extent,
                           VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                               VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                           VK_IMAGE_ASPECT_COLOR_BIT, "frame.hdr");
        hdr_readback_ = Buffer(device_, VkDeviceSize(extent.width) * extent.height * 16,
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, "frame.hdr_readback");
        extent_ = extent;
    }

    // Storage buffers hold at least one element: Vulkan has no empty buffers.
    if (new_spheres)
        sphere_buffer_ = Buffer(device_, sphere_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "scene.spheres");
    // T_sun at the centres (the per-sphere shadow technique) comes later, if a method reads it
    // (ensure_sphere_sun).
    auto* spheres = sphere_buffer_.as<gpu::GpuSphere>();
    for (std::size_t i = 0; i < scene.spheres.size(); ++i) spheres[i] = gpu::to_gpu(scene.spheres[i], eye_, 1.0);
    sphere_sun_done_ = !sun_light_->shadows();

    if (new_boxes)
        box_buffer_ = Buffer(device_, box_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "scene.boxes");
    if (new_grid)
        sun_grid_buffer_ = Buffer(device_, sizeof(gpu::SunGridHeader) + sizeof(std::uint32_t),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "scene.sun_grid");
    // Until a reader asks for the grid (and the map after it), the buffer says there is none.
    sun_header_ = gpu::SunGridHeader{};
    sun_grid_words_.clear();
    sun_grid_done_ = false;
    sun_depth_map_done_ = false;
    sun_map_pending_ = false;
    write_sun_buffer({});
    if (resize || new_spheres || new_boxes || new_grid) write_frame_bindings(descriptors_);
    auto* boxes = box_buffer_.as<gpu::GpuBox>();
    for (std::size_t i = 0; i < scene.boxes.size(); ++i) boxes[i] = gpu::to_gpu(scene.boxes[i], eye_);

    uniforms() = gpu::make_frame_uniforms(scene);
    sphere_count_ = std::uint32_t(scene.spheres.size());
    box_count_ = std::uint32_t(scene.boxes.size());
    background_ = glm::vec3(scene.lighting.background);
}

void FrameResources::write_sun_buffer(std::span<const float> map, std::size_t map_room,
                                      std::span<const std::uint32_t> columns) {
    const std::size_t map_words = std::max(map.size(), map_room);
    const std::size_t words = sun_grid_words_.size() + map_words + columns.size();
    const VkDeviceSize bytes_needed = sizeof(gpu::SunGridHeader) + std::max<std::size_t>(words, 1) * sizeof(std::uint32_t);
    if (sun_grid_buffer_.size() < bytes_needed) {
        device_.wait_idle();  // a presenter's pass of the last frame may still hold the set
        // An eighth more: the map's size wobbles as the smoke moves.
        sun_grid_buffer_ = Buffer(device_, bytes_needed + bytes_needed / 8, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  MemoryUse::Upload, "scene.sun_grid");
        write_frame_bindings(descriptors_);
    }
    auto* bytes = sun_grid_buffer_.as<std::uint8_t>();
    auto* out = reinterpret_cast<std::uint32_t*>(bytes + sizeof(gpu::SunGridHeader));
    // memcpy from an empty vector's data() (null) is undefined even for 0 bytes (UBSan).
    if (!sun_grid_words_.empty()) std::memcpy(out, sun_grid_words_.data(), sun_grid_words_.size() * sizeof(std::uint32_t));
    if (!map.empty()) std::memcpy(out + sun_grid_words_.size(), map.data(), map.size() * sizeof(float));
    if (!columns.empty())
        std::memcpy(out + sun_grid_words_.size() + map_words, columns.data(), columns.size() * sizeof(std::uint32_t));
    std::memcpy(bytes, &sun_header_, sizeof sun_header_);
}

void FrameResources::ensure_sun_grid() {
    if (sun_grid_done_) return;
    sun_grid_done_ = true;
    const SunLight& sun_light = *sun_light_;
    const auto start = std::chrono::steady_clock::now();
    if (sun_light.grid_side() == 0) return;  // no shadows or no spheres, as upload's header says
    const std::size_t grid_words = sun_light.cell_start().size() + sun_light.cell_items().size();
    const VkDeviceSize grid_bytes = sizeof(gpu::SunGridHeader) + grid_words * sizeof(std::uint32_t);
    // A buffer much larger than the scene needs (the smoke thinned out) is made again at its size.
    if (sun_grid_buffer_.size() < grid_bytes ||
        sun_grid_buffer_.size() > 4 * (grid_bytes + map_words_room_ * sizeof(float)) + 4096) {
        device_.wait_idle();  // a presenter's pass of the last frame may still hold the set
        sun_grid_buffer_ = Buffer(device_, grid_bytes + map_words_room_ * sizeof(float) * 9 / 8,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, "scene.sun_grid");
        write_frame_bindings(descriptors_);
    }
    const glm::dvec3 &u = sun_light.grid_u(), &v = sun_light.grid_v();
    // The grid's first cell corner along u and v, relative to the eye as every position on the device.
    sun_header_.u_axis = gpu::vec4(float(u.x), float(u.y), float(u.z), float(sun_light.grid_u0() - glm::dot(eye_, u)));
    sun_header_.v_axis = gpu::vec4(float(v.x), float(v.y), float(v.z), float(sun_light.grid_v0() - glm::dot(eye_, v)));
    sun_header_.cell = gpu::vec4(float(sun_light.grid_cell()), 0.0f, 0.0f, 0.0f);
    const std::vector<std::uint32_t>& outsized = sun_light.outsized_indices();
    sun_header_.size = gpu::uvec4(gpu::uint(sun_light.grid_side()), gpu::uint(sun_light.cell_items().size()), 0u,
                                  gpu::uint(outsized.size()));
    for (std::size_t k = 0; k < outsized.size(); ++k) sun_header_.grid_outsized[k / 4][int(k % 4)] = outsized[k];
    sun_grid_words_.reserve(grid_words);
    sun_grid_words_.insert(sun_grid_words_.end(), sun_light.cell_start().begin(), sun_light.cell_start().end());
    sun_grid_words_.insert(sun_grid_words_.end(), sun_light.cell_items().begin(), sun_light.cell_items().end());
    write_sun_buffer({});
    light_prep_.sun_grid_ms = ms_since(start);
}

void FrameResources::ensure_sphere_sun(const Scene& scene) {
    if (sphere_sun_done_) return;
    const auto start = std::chrono::steady_clock::now();
    // The same code as the reference's per-sphere mode, in double, so the GPU differs from it by float
    // rounding alone.
    auto* spheres = sphere_buffer_.as<gpu::GpuSphere>();
    for (std::size_t i = 0; i < scene.spheres.size(); ++i)
        spheres[i] = gpu::to_gpu(scene.spheres[i], eye_, sun_light_->transmittance(scene.spheres[i].center));
    sphere_sun_done_ = true;
    light_prep_.sphere_sun_ms = ms_since(start);
}

static_assert(gpu::SUN_MAX_OUTSIZED == kMaxOutsized, "the header holds every outsized sphere a grid keeps");
static_assert(gpu::SUN_MAX_WHOLE == SunDepthMap::kMaxWholeSpheres, "the header holds every sphere a map takes whole");
static_assert(sizeof(SunDepthMap::ColumnSphere) == gpu::SUN_COLUMN_WORDS * sizeof(float),
              "a column's sphere is SUN_COLUMN_WORDS words on the device");

void FrameResources::ensure_sun_depth_map(const Scene& scene) {
    if (sun_depth_map_done_) return;
    sun_depth_map_done_ = true;
    ensure_sun_grid();  // the map goes after the grid's words, and its header fields beside the grid's
    if (!scene.lighting.shadows || scene.render.shadow_technique != ShadowTechnique::Accurate ||
        sun_header_.size.x == 0)
        return;  // no map is read, or no sphere casts a shadow (size.x = 0 also tells the shader)
    const auto start = std::chrono::steady_clock::now();
    SunDepthMap& map = sun_depth_map_;
    // On the device only its lattice here (record_sun_map_build fills it); on the host the whole
    // map, in the last frame's memory.
    bool fill_on_device = sun_map_pass_.has_value();
    if (fill_on_device) {
        map.plan(scene, *sun_light_, scene.camera.position);
        // The device's build splats the spheres the grid lists (all but its outsized ones): only where
        // those are the lattice's, not where the map takes a few-sphere scene's every sphere whole
        // (render/sun_depth_map.cpp whole_spheres; its lattice is a handful of zeros).
        // Nor where a sparse cloud's columns take its spheres (the lattice then the least one, of zeros).
        fill_on_device = map.planned() && !map.has_columns() &&
                         map.outsized().size() == sun_light_->outsized_indices().size() &&
                         sun_map_pass_->fits(scene, *sun_light_, map);
    }
    if (!fill_on_device) map.build(scene, *sun_light_, scene.camera.position, 0);
    if (fill_on_device ? !map.planned() : map.empty()) {
        light_prep_.sun_map_ms = ms_since(start);
        return;
    }
    const glm::dvec3 o = map.origin_coordinates();
    sun_header_.map_origin = gpu::vec4(float(o.x), float(o.y), float(o.z), float(map.inverse_cell()));
    sun_header_.map_size = gpu::uvec4(gpu::uint(map.size_u()), gpu::uint(map.size_v()), gpu::uint(map.size_s()),
                                      gpu::uint(sun_grid_words_.size()));
    const std::span<const SunDepthMap::Outsized> outsized = map.outsized();
    sun_header_.size.z = gpu::uint(outsized.size());
    for (std::size_t k = 0; k < outsized.size(); ++k) {
        const SunDepthMap::Outsized& o = outsized[k];
        sun_header_.outsized[k] = gpu::vec4(o.u, o.v, o.s, o.r2);
        sun_header_.outsized_depth[k / 4][int(k % 4)] = o.depth_per_cell;
    }
    const std::size_t vertices = std::size_t(map.size_u()) * std::size_t(map.size_v()) * std::size_t(map.size_s());
    // A sparse cloud's columns (render/sun_depth_map.h Columns) after the map: the offsets, then the
    // spheres, SUN_COLUMN_WORDS words each.
    std::vector<std::uint32_t>& column_words = sun_column_words_;  // kept from frame to frame for its memory
    column_words.clear();
    if (map.has_columns()) {
        const SunDepthMap::Columns& columns = map.columns();
        const std::size_t first = sun_grid_words_.size() + vertices;
        sun_header_.columns = gpu::vec4(columns.u0, columns.v0, columns.inverse_side, 0.0f);
        sun_header_.column_size = gpu::uvec4(gpu::uint(columns.nu), gpu::uint(columns.nv), gpu::uint(first),
                                             gpu::uint(first + columns.first.size()));
        column_words.reserve(columns.first.size() + columns.spheres.size() * gpu::SUN_COLUMN_WORDS);
        column_words.insert(column_words.end(), columns.first.begin(), columns.first.end());
        for (const SunDepthMap::ColumnSphere& c : columns.spheres)
            for (const float f : {c.u, c.v, c.s, c.r2, c.depth_per_cell, c.top})
                column_words.push_back(std::bit_cast<std::uint32_t>(f));
    }
    write_sun_buffer(map.values(), vertices, column_words);
    sun_map_words_ = vertices + column_words.size();
    sun_map_pending_ = fill_on_device;
    light_prep_.sun_map_ms = ms_since(start);
}

bool FrameResources::record_sun_map_build(VkCommandBuffer cmd) const {
    if (!sun_map_pending_) return false;
    sun_map_pass_->record(cmd, descriptors_, sun_depth_map_);
    return true;
}

void FrameResources::record_opaque_pass(VkCommandBuffer cmd) const {
    image_barrier(cmd, opaque_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    image_barrier(cmd, depth_image_.get(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, 0,
                  VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                  VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);

    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = opaque_image_.view();
    color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{background_.r, background_.g, background_.b, INFINITY}};
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = depth_image_.view();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.clearValue.depthStencil = {0.0f, 0};
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent_};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &info);
    if (box_count_ > 0) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, opaque_pipeline_);
        descriptors_.bind(cmd);
        set_viewport(cmd, extent_);
        vkCmdDraw(cmd, 6, box_count_, 0, 0);
    }
    vkCmdEndRendering(cmd);

    // Later passes read radiance and distance as a storage image.
    image_barrier(cmd, opaque_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

void FrameResources::begin_hdr_rendering(VkCommandBuffer cmd) const {
    // Source stages: the last frame's readback copy or a presenter's sampling of the target.
    image_barrier(cmd, hdr_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = hdr_image_.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent_};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &info);
    set_viewport(cmd, extent_);
}

void FrameResources::end_hdr_rendering(VkCommandBuffer cmd) const { vkCmdEndRendering(cmd); }

void FrameResources::draw_spheres(VkCommandBuffer cmd, VkPipeline pipeline,
                                  const SharedDescriptors& descriptors) const {
    if (sphere_count_ == 0) return;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    descriptors.bind(cmd);
    set_viewport(cmd, extent_);
    vkCmdDraw(cmd, 6, sphere_count_, 0, 0);
}

void FrameResources::resolve_to_hdr(VkCommandBuffer cmd, VkPipeline pipeline,
                                    const SharedDescriptors& descriptors) const {
    begin_hdr_rendering(cmd);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    descriptors.bind(cmd);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    end_hdr_rendering(cmd);
}

void FrameResources::copy_to_hdr(VkCommandBuffer cmd, VkBuffer radiance) const {
    // Source stages as begin_hdr_rendering's: the last frame's readback copy or a presenter's sampling.
    image_barrier(cmd, hdr_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0,
                  VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent_.width, extent_.height, 1};
    vkCmdCopyBufferToImage(cmd, radiance, hdr_image_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    // Into the layout and the stage that record_hdr_readback and record_hdr_to_sampled start from.
    image_barrier(cmd, hdr_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

void FrameResources::record_hdr_readback(VkCommandBuffer cmd) const {
    image_barrier(cmd, hdr_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    copy_image_to_host(cmd, hdr_image_.get(), extent_, hdr_readback_.get());
}

void FrameResources::record_hdr_to_sampled(VkCommandBuffer cmd) const {
    image_barrier(cmd, hdr_image_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                  VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

Image FrameResources::read_hdr() const {
    Image image(int(extent_.width), int(extent_.height));
    const float* rgba = hdr_readback_.as<const float>();
    const std::size_t pixels = std::size_t(extent_.width) * extent_.height;
    for (std::size_t p = 0; p < pixels; ++p) std::memcpy(&image.rgb[p * 3], &rgba[p * 4], 3 * sizeof(float));
    return image;
}

}  // namespace brume
