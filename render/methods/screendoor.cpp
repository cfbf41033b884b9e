#include "render/methods/screendoor.h"

#include "fullscreen_ray.vert.h"
#include "render/vk/pipelines.h"
#include "screendoor_resolve.frag.h"
#include "screendoor_spheres.frag.h"
#include "sphere_impostor.vert.h"

#include <algorithm>
#include <stdexcept>

namespace brume {

using namespace vk;

ScreendoorMethod::ScreendoorMethod(Device& device, int samples)
    : GpuMethod(device), samples_(samples) {
    if (samples < 1 || samples > kMaxSamples)
        throw std::invalid_argument("screendoor: S must be 1.." + std::to_string(kMaxSamples) + " (got " +
                                    std::to_string(samples) + ")");
    // Specialization constant 0: S, in both fragment shaders.
    const std::vector<std::uint32_t> constants = {std::uint32_t(samples)};
    GraphicsPipelineDesc spheres;
    spheres.name = "screendoor_spheres";
    spheres.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    spheres.fragment = BRUME_SPIRV(spv_screendoor_spheres_frag);
    spheres.color_formats = {kColorFormat};
    spheres.depth_format = FrameResources::kDepthFormat;
    spheres.depth_compare = VK_COMPARE_OP_GREATER;  // depth = 1/(1+t): nearer is larger
    spheres.fragment_constants = constants;
    sphere_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), spheres);

    GraphicsPipelineDesc resolve;
    resolve.name = "screendoor_resolve";
    resolve.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    resolve.fragment = BRUME_SPIRV(spv_screendoor_resolve_frag);
    resolve.color_formats = {FrameResources::kHdrFormat};
    resolve.fragment_constants = constants;
    resolve_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), resolve);
}

std::uint64_t ScreendoorMethod::target_bytes(int samples, std::uint32_t width, std::uint32_t height) {
    const std::uint64_t subsamples = std::uint64_t(samples) * samples * width * height;
    return subsamples * (16 + 4);  // RGBA32F colour + D32 depth
}

void ScreendoorMethod::ensure_targets(VkExtent2D extent) {
    if (extent.width == extent_.width && extent.height == extent_.height) return;
    const VkPhysicalDeviceLimits& limits = device_.properties().limits;
    const std::uint64_t w = std::uint64_t(extent.width) * samples_, h = std::uint64_t(extent.height) * samples_;
    const std::uint64_t max_w = std::min(limits.maxImageDimension2D, limits.maxFramebufferWidth);
    const std::uint64_t max_h = std::min(limits.maxImageDimension2D, limits.maxFramebufferHeight);
    if (w > max_w || h > max_h)
        throw std::runtime_error("screendoor:" + std::to_string(samples_) + " renders " + std::to_string(extent.width) +
                                 "x" + std::to_string(extent.height) + " at " + std::to_string(w) + "x" +
                                 std::to_string(h) + ", beyond this device's " + std::to_string(max_w) + "x" +
                                 std::to_string(max_h) + " limit; lower S or the resolution");
    const std::uint64_t bytes = target_bytes(samples_, extent.width, extent.height);
    const std::uint64_t budget = device_.device_local_bytes() / 2;
    if (bytes > budget)
        throw std::runtime_error("screendoor:" + std::to_string(samples_) + " needs " + format_bytes(bytes) +
                                 " of supersampled targets at " + std::to_string(extent.width) + "x" +
                                 std::to_string(extent.height) + ", more than half the device's memory (" +
                                 format_bytes(budget) + "); lower S or the resolution");
    color_ = DeviceImage();  // free the old targets before allocating the new ones
    depth_ = DeviceImage();
    const VkExtent2D big{std::uint32_t(w), std::uint32_t(h)};
    color_ = DeviceImage(device_, kColorFormat, big, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT,
                         VK_IMAGE_ASPECT_COLOR_BIT, "screendoor.color");
    depth_ = DeviceImage(device_, FrameResources::kDepthFormat, big, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                         VK_IMAGE_ASPECT_DEPTH_BIT, "screendoor.depth");
    descriptors_.write_storage_image(gpu::BINDING_SCREENDOOR_SUBSAMPLES, color_.view());
    extent_ = extent;
}

bool ScreendoorMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {

    // Supersampled sphere pass. The previous frame's resolve read the colour target: a write-after-read,
    // so an execution dependency on the fragment stage is enough before it is cleared.
    image_barrier(cmd, color_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    image_barrier(cmd, depth_.get(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, 0,
                  VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                  VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = color_.view();
    color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};  // a = 0: no sphere kept here
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = depth_.view();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.clearValue.depthStencil = {0.0f, 0};  // infinitely far
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, color_.extent()};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &info);
    if (ctx.sphere_count() > 0) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sphere_pipeline_);
        ctx.bind(cmd);
        set_viewport(cmd, color_.extent());
        vkCmdDraw(cmd, 6, ctx.sphere_count(), 0, 0);
    }
    vkCmdEndRendering(cmd);
    ctx.mark(cmd, "spheres x" + std::to_string(samples_ * samples_));
    image_barrier(cmd, color_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

    // Box filter down into the HDR target.
    ctx.resolve_to_hdr(cmd, resolve_pipeline_);
    ctx.mark(cmd, "box filter");
    return true;
}

void ScreendoorMethod::prepare(FrameContext& ctx) { ensure_targets(ctx.extent()); }

void ScreendoorMethod::report(FrameStats& stats, const FrameContext&) {
    stats.memory_bytes = target_bytes(samples_, extent_.width, extent_.height);
}

int parse_screendoor_setting(const std::string& setting) {
    if (setting.empty()) return ScreendoorMethod::kDefaultSamples;
    const bool digits = setting.size() <= 2 && std::all_of(setting.begin(), setting.end(), [](char c) {
                            return c >= '0' && c <= '9';
                        });
    const int samples = digits ? std::stoi(setting) : 0;
    if (samples < 1 || samples > ScreendoorMethod::kMaxSamples)
        throw std::invalid_argument("method 'screendoor' takes S, sub-samples per pixel along each axis, 1.." +
                                    std::to_string(ScreendoorMethod::kMaxSamples) + " (got ':" + setting + "')");
    return samples;
}

std::unique_ptr<Method> make_screendoor_method(Device& device, const std::string& setting) {
    return std::make_unique<ScreendoorMethod>(device, parse_screendoor_setting(setting));
}

}  // namespace brume
