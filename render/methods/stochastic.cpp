#include "render/methods/stochastic.h"

#include "fullscreen_ray.vert.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"
#include "stochastic_alpha.frag.h"
#include "stochastic_cover.frag.h"
#include "stochastic_depth_accum.frag.h"
#include "stochastic_depth_resolve.frag.h"
#include "sphere_impostor.vert.h"
#include "stochastic_resolve.frag.h"

#include <stdexcept>

namespace brume {

using namespace vk;

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // per sample: (colour, 1) or 0
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;           // 1 / (1 + t_entry), nearer is larger
constexpr VkFormat kAccumFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // (sum alpha c, sum alpha)
constexpr VkFormat kOpticalDepthFormat = VK_FORMAT_R32_SFLOAT;    // sum tau * chord
constexpr VkFormat kDepthLayerFormat = VK_FORMAT_R32_SFLOAT;      // ",depth": nearest covering t_entry
constexpr float kNoDepth = 3.0e38f;                               // ",depth": no sphere covers the sample
constexpr std::uint32_t kMaxSamples = 64;

// An image with any sample and layer count (DeviceImage has one of each): a view of the whole array
// and one 2D view per layer.

std::uint32_t parse_count(const std::string& text, const std::string& what) {
    if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument(what + ": expected a whole number (got '" + text + "')");
    return std::uint32_t(std::stoul(text));
}

}  // namespace

StochasticOptions parse_stochastic_setting(const std::string& setting) {
    StochasticOptions options;
    if (setting.empty()) return options;
    std::string count = setting;
    const std::size_t comma = setting.find(',');
    if (comma != std::string::npos) {
        const std::string flag = setting.substr(comma + 1);
        if (flag == "plain")
            options.alpha_correction = false;
        else if (flag == "depth")
            options.depth_based = true;
        else
            throw std::invalid_argument("stochastic: unknown option '" + flag + "' (known: 'plain', 'depth')");
        count = setting.substr(0, comma);
    }
    const std::string what = "stochastic: samples per pixel";
    options.samples = parse_count(count, what);
    if (options.samples == 0 || options.samples > kMaxSamples || (options.samples & (options.samples - 1)))
        throw std::invalid_argument(what + " must be a power of two from 1 to " + std::to_string(kMaxSamples) +
                                    " (got " + count + ")");
    return options;
}

struct StochasticMethod::Targets {
    DeviceImage msaa_color;  // only with 4-sample passes
    DeviceImage depth;
    DeviceImage resolved;    // the MSAA resolve of the current pass (only with 4-sample passes)
    DeviceImage layers;      // one resolved (averaged) layer per pass
    DeviceImage accum;
    DeviceImage optical_depth;
    VkExtent2D extent{};
};

StochasticMethod::StochasticMethod(Device& device, StochasticOptions options)
    : GpuMethod(device),
      options_(options),
      pass_samples_(options.samples >= 4 && !options.depth_based ? 4u : 1u),
      passes_(options.samples / pass_samples_) {
    if (options.samples == 0 || options.samples > kMaxSamples || (options.samples & (options.samples - 1)))
        throw std::invalid_argument("stochastic: samples per pixel must be a power of two from 1 to 64");
    if (options.depth_based && !options.alpha_correction)
        throw std::invalid_argument("stochastic: ',depth' is always alpha-corrected (no ',plain')");

    GraphicsPipelineDesc alpha;
    alpha.name = "stochastic_alpha";
    alpha.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    alpha.fragment = BRUME_SPIRV(spv_stochastic_alpha_frag);
    alpha.color_formats = {kAccumFormat, kOpticalDepthFormat};
    alpha.blends = {blend_additive(), blend_additive()};
    alpha_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), alpha);

    GraphicsPipelineDesc cover;
    cover.name = "stochastic_cover";
    cover.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    cover.fragment = BRUME_SPIRV(spv_stochastic_cover_frag);
    cover.color_formats = {options.depth_based ? kDepthLayerFormat : kColorFormat};
    cover.depth_format = kDepthFormat;
    cover.depth_compare = VK_COMPARE_OP_GREATER;  // depth = 1 / (1 + t): nearer is larger
    cover.samples = VkSampleCountFlagBits(pass_samples_);
    cover.fragment_constants = {options.samples, pass_samples_, options.depth_based ? 1u : 0u};
    cover_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), cover);

    GraphicsPipelineDesc resolve;
    resolve.name = "stochastic_resolve";
    resolve.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    resolve.fragment = options.depth_based ? BRUME_SPIRV(spv_stochastic_depth_resolve_frag)
                                           : BRUME_SPIRV(spv_stochastic_resolve_frag);
    resolve.color_formats = {FrameResources::kHdrFormat};
    if (!options.depth_based) resolve.fragment_constants = {passes_, options.alpha_correction ? 1u : 0u};
    resolve_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), resolve);

    if (options.depth_based) {
        GraphicsPipelineDesc accum = alpha;
        accum.name = "stochastic_depth_accum";
        accum.fragment = BRUME_SPIRV(spv_stochastic_depth_accum_frag);
        accum.fragment_constants = {options.samples};
        depth_accum_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), accum);
    }
}

StochasticMethod::~StochasticMethod() = default;

std::string StochasticMethod::name() const {
    return "stochastic:" + std::to_string(options_.samples) +
           (options_.depth_based ? ",depth" : options_.alpha_correction ? "" : ",plain");
}

void StochasticMethod::ensure_targets(VkExtent2D extent) {
    if (targets_ && targets_->extent.width == extent.width && targets_->extent.height == extent.height) return;
    targets_.reset();
    auto t = std::make_unique<Targets>();
    const VkSampleCountFlagBits samples = VkSampleCountFlagBits(pass_samples_);
    if (pass_samples_ > 1) {
        t->msaa_color = DeviceImage(device_, kColorFormat, extent, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
                                    VK_IMAGE_ASPECT_COLOR_BIT, "stochastic.msaa_color", samples);
        t->resolved = DeviceImage(device_, kColorFormat, extent,
                                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                  VK_IMAGE_ASPECT_COLOR_BIT, "stochastic.resolved");
    }
    t->depth = DeviceImage(device_, kDepthFormat, extent, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                           VK_IMAGE_ASPECT_DEPTH_BIT, "stochastic.depth", samples);
    const VkImageUsageFlags storage_target = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    t->layers = DeviceImage(device_, options_.depth_based ? kDepthLayerFormat : kColorFormat, extent, storage_target | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                            VK_IMAGE_ASPECT_COLOR_BIT, "stochastic.layers", VK_SAMPLE_COUNT_1_BIT, passes_,
                            /*array=*/true);
    t->accum = DeviceImage(device_, kAccumFormat, extent, storage_target, VK_IMAGE_ASPECT_COLOR_BIT, "stochastic.accum");
    t->optical_depth = DeviceImage(device_, kOpticalDepthFormat, extent, storage_target, VK_IMAGE_ASPECT_COLOR_BIT,
                                   "stochastic.optical_depth");
    t->extent = extent;
    descriptors_.write_storage_image(gpu::BINDING_STOCHASTIC_LAYERS, t->layers.view());
    descriptors_.write_storage_image(gpu::BINDING_STOCHASTIC_ACCUM, t->accum.view());
    descriptors_.write_storage_image(gpu::BINDING_STOCHASTIC_OPTICAL_DEPTH, t->optical_depth.view());
    targets_ = std::move(t);
}

bool StochasticMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    Targets& t = *targets_;

    // Total alpha (alpha correction): sum(alpha c), sum(alpha) and the optical depth, additively.
    // Without the correction the resolve does not read these targets, but they still need a layout.
    for (VkImage image : {t.accum.get(), t.optical_depth.get()})
        image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    const auto accum_written = [&] {
        for (VkImage image : {t.accum.get(), t.optical_depth.get()})
            image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                          VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    };
    if (options_.depth_based) {
        // Depth layers first, then one pass accumulates the visibility-weighted colour and the
        // optical depth into the same targets the total-alpha pass uses.
        record_coverage(cmd, ctx);
        ctx.mark(cmd, "depth x" + std::to_string(passes_));
        record_accumulation(cmd, ctx, depth_accum_pipeline_);
        accum_written();
        ctx.mark(cmd, "accumulate");
    } else {
        if (options_.alpha_correction) record_accumulation(cmd, ctx, alpha_pipeline_);
        accum_written();
        ctx.mark(cmd, "total alpha");
        record_coverage(cmd, ctx);
        ctx.mark(cmd, "coverage x" + std::to_string(passes_));
    }

    ctx.resolve_to_hdr(cmd, resolve_pipeline_);
    ctx.mark(cmd, "resolve");
    return true;
}

// Renders every sphere once with `pipeline` into accum (target 0) and optical_depth (target 1),
// cleared first; the targets are in GENERAL. Either the total-alpha pass or the ",depth"
// accumulation pass.
void StochasticMethod::record_accumulation(VkCommandBuffer cmd, const FrameContext& ctx, VkPipeline pipeline) {
    Targets& t = *targets_;
    const bool draw = ctx.sphere_count() > 0;
    VkRenderingAttachmentInfo targets[2] = {{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                            {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO}};
    targets[0].imageView = t.accum.view();
    targets[1].imageView = t.optical_depth.view();
    for (VkRenderingAttachmentInfo& a : targets) {
        a.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
        a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        a.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    }
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, t.extent};
    info.layerCount = 1;
    info.colorAttachmentCount = 2;
    info.pColorAttachments = targets;
    vkCmdBeginRendering(cmd, &info);
    if (draw) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        ctx.bind(cmd);
        set_viewport(cmd, t.extent);
        vkCmdDraw(cmd, 6, ctx.sphere_count(), 0, 0);
    }
    vkCmdEndRendering(cmd);
}

// The S samples: passes_ geometry passes into the layers (left in GENERAL, readable by fragment
// shaders). ",depth": each layer holds one sample's nearest covering t_entry.
void StochasticMethod::record_coverage(VkCommandBuffer cmd, const FrameContext& ctx) {
    Targets& t = *targets_;
    const bool draw = ctx.sphere_count() > 0;
    // Coverage passes: pass p owns samples p * pass_samples_ .. (p + 1) * pass_samples_ - 1.
    // Single-sample passes render straight into layer p. 4-sample passes resolve (average) into a 2D
    // image that is copied into layer p: lavapipe 22.3 resolves into layer 0 whatever layer the
    // resolve view names.
    const bool msaa = pass_samples_ > 1;
    const VkImageLayout layers_layout = msaa ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
    image_barrier(cmd, t.layers.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, layers_layout, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, msaa ? VK_PIPELINE_STAGE_2_COPY_BIT : VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, msaa ? VK_ACCESS_2_TRANSFER_WRITE_BIT
                        : VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, passes_);
    const VkPipelineStageFlags2 depth_stages =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    const VkAccessFlags2 depth_access =
        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    const VkAccessFlags2 color_access = VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    for (std::uint32_t p = 0; p < passes_; ++p) {
        // Every pass clears the MSAA colour and depth and rewrites the resolve target: each starts
        // from UNDEFINED, after the previous pass's tests, resolve and copy.
        image_barrier(cmd, t.depth.get(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, depth_stages, depth_access, depth_stages, depth_access, 1);
        if (msaa) {
            image_barrier(cmd, t.msaa_color.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, color_access, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, color_access, 1);
            image_barrier(cmd, t.resolved.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, color_access, 1);
        }
        VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color.clearValue.color = {{options_.depth_based ? kNoDepth : 0.0f, 0.0f, 0.0f, 0.0f}};
        if (msaa) {
            color.imageView = t.msaa_color.layer_view(0);
            color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
            color.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
            color.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
            color.resolveImageView = t.resolved.layer_view(0);
            color.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        } else {
            color.imageView = t.layers.layer_view(p);
            color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
            color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        }
        VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depth.imageView = t.depth.layer_view(0);
        depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depth.clearValue.depthStencil = {0.0f, 0};
        VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
        info.renderArea = {{0, 0}, t.extent};
        info.layerCount = 1;
        info.colorAttachmentCount = 1;
        info.pColorAttachments = &color;
        info.pDepthAttachment = &depth;
        vkCmdBeginRendering(cmd, &info);
        if (draw) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, cover_pipeline_);
            ctx.bind(cmd);
            set_viewport(cmd, t.extent);
            // firstVertex tells the vertex shader the pass (gl_VertexIndex / 6): no push constants.
            vkCmdDraw(cmd, 6, ctx.sphere_count(), 6 * p, 0);
        }
        vkCmdEndRendering(cmd);
        if (msaa) {
            image_barrier(cmd, t.resolved.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, 1);
            VkImageCopy region{};
            region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, p, 1};
            region.extent = {t.extent.width, t.extent.height, 1};
            vkCmdCopyImage(cmd, t.resolved.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, t.layers.get(),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        }
    }
    image_barrier(cmd, t.layers.get(), VK_IMAGE_ASPECT_COLOR_BIT, layers_layout, VK_IMAGE_LAYOUT_GENERAL, msaa ? VK_PIPELINE_STAGE_2_COPY_BIT : VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, msaa ? VK_ACCESS_2_TRANSFER_WRITE_BIT : VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, passes_);
}

void StochasticMethod::prepare(FrameContext& ctx) { ensure_targets(ctx.extent()); }

void StochasticMethod::report(FrameStats& stats, const FrameContext&) {
    const Targets& t = *targets_;
    const std::uint64_t pixels = std::uint64_t(t.extent.width) * t.extent.height;
    stats.memory_bytes = t.msaa_color.bytes() + t.resolved.bytes() + t.depth.bytes() + t.layers.bytes() + pixels * (16 + 4);
}

std::unique_ptr<Method> make_stochastic_method(Device& device, const std::string& setting) {
    return std::make_unique<StochasticMethod>(device, parse_stochastic_setting(setting));
}

}  // namespace brume
