#include "render/methods/weighted.h"

#include "fullscreen_ray.vert.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"
#include "sphere_impostor.vert.h"
#include "weighted_accumulate.frag.h"
#include "weighted_composite.frag.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <stdexcept>

namespace brume {

using namespace vk;

namespace {

constexpr VkFormat kAccumFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kExtraFormat = VK_FORMAT_R32_SFLOAT;

using gpu::WeightParams;

const char* mode_name(WeightedMode mode) {
    switch (mode) {
    case WeightedMode::Sum: return "wsum";
    case WeightedMode::Average: return "wavg";
    case WeightedMode::Blended: return "wboit";
    }
    return "?";
}

void require_no_setting(const char* name, const std::string& setting) {
    if (!setting.empty())
        throw std::invalid_argument(std::string("method '") + name + "' takes no setting (got ':" + setting + "')");
}

}  // namespace

WeightedMethod::WeightedMethod(Device& device, WeightedMode mode)
    : GpuMethod(device), mode_(mode) {
    const std::vector<std::uint32_t> constants = {std::uint32_t(mode)};

    GraphicsPipelineDesc accumulate;
    accumulate.name = std::string(mode_name(mode)) + "_accumulate";
    accumulate.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    accumulate.fragment = BRUME_SPIRV(spv_weighted_accumulate_frag);
    accumulate.color_formats = {kAccumFormat, kExtraFormat};
    accumulate.blends = {blend_additive(), blend_additive()};
    accumulate.fragment_constants = constants;
    accumulate_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), accumulate);

    GraphicsPipelineDesc composite;
    composite.name = std::string(mode_name(mode)) + "_composite";
    composite.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    composite.fragment = BRUME_SPIRV(spv_weighted_composite_frag);
    composite.color_formats = {FrameResources::kHdrFormat};
    composite.fragment_constants = constants;
    composite_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), composite);

    params_ = Buffer(device, sizeof(WeightParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload,
                     std::string(mode_name(mode)) + ".params");
    descriptors_.write_storage(gpu::BINDING_WEIGHT_PARAMS, params_.get());
}

std::string WeightedMethod::name() const { return mode_name(mode_); }

double WeightedMethod::weight_depth_scale(const Scene& scene) {
    double z_max = 0.0;
    for (const Sphere& s : scene.spheres)
        if (s.extinction > 0.0) z_max = std::max(z_max, glm::length(s.center - scene.camera.position) + s.radius);
    return z_max > 0.0 ? z_max / 1.32 : 1.0;
}

void WeightedMethod::ensure_targets(VkExtent2D extent) {
    if (accum_.extent().width == extent.width && accum_.extent().height == extent.height) return;
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    const std::string prefix = mode_name(mode_);
    accum_ = DeviceImage(device_, kAccumFormat, extent, usage, VK_IMAGE_ASPECT_COLOR_BIT, prefix + ".accum");
    extra_ = DeviceImage(device_, kExtraFormat, extent, usage, VK_IMAGE_ASPECT_COLOR_BIT, prefix + ".extra");
    descriptors_.write_storage_image(gpu::BINDING_WEIGHT_ACCUM, accum_.view());
    descriptors_.write_storage_image(gpu::BINDING_WEIGHT_EXTRA, extra_.view());
}

bool WeightedMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {

    // Accumulation: both targets cleared to zero, every sphere fragment added.
    for (VkImage image : {accum_.get(), extra_.get()})
        image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    begin_color_rendering(cmd, ctx.extent(), {accum_.view(), extra_.view()}, VK_ATTACHMENT_LOAD_OP_CLEAR);
    ctx.draw_spheres(cmd, accumulate_pipeline_);
    vkCmdEndRendering(cmd);
    ctx.mark(cmd, "accumulate");
    for (VkImage image : {accum_.get(), extra_.get()})
        image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

    ctx.resolve_to_hdr(cmd, composite_pipeline_);
    ctx.mark(cmd, "composite");
    return true;
}

void WeightedMethod::prepare(FrameContext& ctx) {
    ensure_targets(ctx.extent());
    params_.as<WeightParams>()->depth.x = float(weight_depth_scale(ctx.scene()));
}

void WeightedMethod::report(FrameStats& stats, const FrameContext& ctx) {
    const std::uint64_t pixels = std::uint64_t(ctx.extent().width) * ctx.extent().height;
    stats.memory_bytes = pixels * (16 + 4) + params_.size();
}

std::unique_ptr<Method> make_wsum_method(Device& device, const std::string& setting) {
    require_no_setting("wsum", setting);
    return std::make_unique<WeightedMethod>(device, WeightedMode::Sum);
}

std::unique_ptr<Method> make_wavg_method(Device& device, const std::string& setting) {
    require_no_setting("wavg", setting);
    return std::make_unique<WeightedMethod>(device, WeightedMode::Average);
}

std::unique_ptr<Method> make_wboit_method(Device& device, const std::string& setting) {
    require_no_setting("wboit", setting);
    return std::make_unique<WeightedMethod>(device, WeightedMode::Blended);
}

}  // namespace brume
