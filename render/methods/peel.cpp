#include "render/methods/peel.h"

#include "peel_classic.frag.h"
#include "peel_composite.frag.h"
#include "peel_dual.frag.h"
#include "peel_dual_composite.frag.h"
#include "peel_dual_resolve.frag.h"
#include "peel_fullscreen.vert.h"
#include "sphere_impostor.vert.h"
#include "peel_resolve.frag.h"
#include "peel_tail.frag.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>

namespace brume {

using namespace vk;

namespace {

using gpu::PeelControl;
constexpr int kMaxPasses = int(gpu::PEEL_MAX_PASSES);
constexpr std::uint32_t kSlots = gpu::PEEL_SLOTS;
static_assert(sizeof(VkDrawIndirectCommand) == sizeof(glm::uvec4), "PeelControl's draw arguments");

constexpr std::uint32_t kNoKey = 0xffffffffu;

// Between the passes of a frame: every attachment, storage and indirect-argument write before is
// visible to every such access after (images stay in GENERAL, so one global barrier covers them).
void pass_barrier(VkCommandBuffer cmd) {
    constexpr VkPipelineStageFlags2 stages =
        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    memory_barrier(cmd, stages,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                   stages | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                   VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT |
                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
                       VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
}

VkRenderingAttachmentInfo attachment(VkImageView view, VkAttachmentLoadOp load, VkAttachmentStoreOp store,
                                     VkClearValue clear = {}, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL) {
    VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    a.imageView = view;
    a.imageLayout = layout;
    a.loadOp = load;
    a.storeOp = store;
    a.clearValue = clear;
    return a;
}

VkClearValue clear_float(float r, float g, float b, float a) {
    VkClearValue v{};
    v.color.float32[0] = r;
    v.color.float32[1] = g;
    v.color.float32[2] = b;
    v.color.float32[3] = a;
    return v;
}

int parse_passes(const std::string& text, const std::string& setting) {
    const std::string allowed = "method 'peel' takes N or dual:N (peel:N, peel:dual:N) with N in 1.." +
                                std::to_string(kMaxPasses) + " (got ':" + setting + "')";
    if (text.empty() || text.size() > 3 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw std::invalid_argument(allowed);
    const int n = std::stoi(text);
    if (n < 1 || n > kMaxPasses) throw std::invalid_argument(allowed);
    return n;
}

}  // namespace

PeelOptions parse_peel_setting(const std::string& setting) {
    PeelOptions o;
    if (setting.empty()) return o;
    // "dual" alone is refused with the rest (parse_passes of ""): like "kbuf:", a setting left half
    // written, which rendered peel:dual:8 unasked.
    if (setting.rfind("dual:", 0) == 0) {
        o.dual = true;
        o.passes = parse_passes(setting.substr(5), setting);
        return o;
    }
    o.passes = parse_passes(setting, setting);
    return o;
}

std::unique_ptr<Method> make_peel_method(Device& device, const std::string& setting) {
    return std::make_unique<PeelMethod>(device, parse_peel_setting(setting));
}

namespace {
const PeelOptions& checked(const PeelOptions& options) {
    if (options.passes < 1 || options.passes > kMaxPasses)
        throw std::invalid_argument("peel: passes must be in 1.." + std::to_string(kMaxPasses) + " (got " +
                                    std::to_string(options.passes) + ")");
    if (options.passes_per_submit < 1) throw std::invalid_argument("peel: passes_per_submit must be at least 1");
    return options;
}
}  // namespace

PeelMethod::PeelMethod(Device& device, PeelOptions options)
    : GpuMethod(device),
      options_(checked(options)),
      geometry_passes_(options.dual ? options.passes + 1 : options.passes) {
    const std::vector<std::uint32_t> constants = {std::uint32_t(geometry_passes_)};

    GraphicsPipelineDesc peel;
    peel.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    if (options.dual) {
        peel.name = "peel_dual";
        peel.fragment = BRUME_SPIRV(spv_peel_dual_frag);
        peel.color_formats.assign(2, VK_FORMAT_R32G32B32A32_SFLOAT);  // window, ids
        // Every output of a dual peel pass takes the maximum: one blend state for all attachments,
        // since the device does not enable independentBlend.
        peel.blends = {blend_max(), blend_max()};
    } else {
        peel.name = "peel_classic";
        peel.fragment = BRUME_SPIRV(spv_peel_classic_frag);
        peel.color_formats = {VK_FORMAT_R32G32B32A32_UINT};  // key
        peel.depth_format = VK_FORMAT_D32_SFLOAT;
        peel.depth_compare = VK_COMPARE_OP_LESS;  // equal depths: the first drawn, the lowest index, stays
    }
    peel_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), peel);

    GraphicsPipelineDesc tail;
    tail.name = "peel_tail";
    tail.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    tail.fragment = BRUME_SPIRV(spv_peel_tail_frag);
    tail.color_formats = {VK_FORMAT_R32G32B32A32_SFLOAT};
    tail.blends = {blend_additive()};
    tail_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), tail);

    GraphicsPipelineDesc composite;
    composite.name = options.dual ? "peel_dual_composite" : "peel_composite";
    composite.vertex = BRUME_SPIRV(spv_peel_fullscreen_vert);
    composite.fragment = options.dual ? BRUME_SPIRV(spv_peel_dual_composite_frag) : BRUME_SPIRV(spv_peel_composite_frag);
    composite.fragment_constants = constants;
    composite_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), composite);

    GraphicsPipelineDesc resolve;
    resolve.name = options.dual ? "peel_dual_resolve" : "peel_resolve";
    resolve.vertex = BRUME_SPIRV(spv_peel_fullscreen_vert);
    resolve.fragment = options.dual ? BRUME_SPIRV(spv_peel_dual_resolve_frag) : BRUME_SPIRV(spv_peel_resolve_frag);
    resolve.color_formats = {FrameResources::kHdrFormat};
    if (!options.dual) resolve.fragment_constants = constants;
    resolve_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), resolve);

    control_ = Buffer(device, sizeof(PeelControl),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                          VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                      MemoryUse::Device, "peel.control");
    control_readback_ = Buffer(device, sizeof(PeelControl), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback,
                               "peel.control_readback");
    descriptors_.write_storage(gpu::BINDING_PEEL_CONTROL, control_.get());
}

std::string PeelMethod::name() const {
    return std::string("peel:") + (options_.dual ? "dual:" : "") + std::to_string(options_.passes);
}

void PeelMethod::ensure_targets(VkExtent2D extent) {
    if (extent.width == extent_.width && extent.height == extent_.height) return;
    images_.clear();
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    auto add = [&](VkFormat format, VkImageUsageFlags u, const char* name, std::uint32_t binding) {
        images_.emplace_back(device_, format, extent, u, VK_IMAGE_ASPECT_COLOR_BIT, name);
        descriptors_.write_storage_image(binding, images_.back().view());
    };
    if (options_.dual) {
        add(VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, "peel.state", gpu::BINDING_PEEL_STATE);
        add(VK_FORMAT_R32G32B32A32_SFLOAT, usage, "peel.window", gpu::BINDING_PEEL_WINDOW);
        add(VK_FORMAT_R32G32B32A32_SFLOAT, usage, "peel.tail", gpu::BINDING_PEEL_TAIL);
        add(VK_FORMAT_R32G32B32A32_SFLOAT, usage, "peel.ids", gpu::BINDING_PEEL_IDS);
        depth_ = DeviceImage();
    } else {
        add(VK_FORMAT_R32G32B32A32_UINT, usage, "peel.keys0", gpu::BINDING_PEEL_KEYS0);
        add(VK_FORMAT_R32G32B32A32_UINT, usage, "peel.keys1", gpu::BINDING_PEEL_KEYS1);
        add(VK_FORMAT_R32G32B32A32_SFLOAT, usage, "peel.tail", gpu::BINDING_PEEL_TAIL);
        depth_ = DeviceImage(device_, VK_FORMAT_D32_SFLOAT, extent, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                             VK_IMAGE_ASPECT_DEPTH_BIT, "peel.depth");
    }
    const VkDeviceSize pixels = VkDeviceSize(extent.width) * extent.height;
    accum_ = Buffer(device_, pixels * 16 * (options_.dual ? 3 : 2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                    MemoryUse::Device, "peel.accum");
    descriptors_.write_storage(gpu::BINDING_PEEL_ACCUM, accum_.get());
    extent_ = extent;
}

void PeelMethod::record_start(VkCommandBuffer cmd, const FrameContext& ctx) {
    // Pass 0 and its composite always run; the composites switch the later ones on.
    PeelControl control{};
    for (std::uint32_t p = 0; p < kSlots; ++p) {
        control.peel_args[p] = glm::uvec4(6, 0, 6 * p, 0);
        control.composite_args[p] = glm::uvec4(3, 0, 3 * p, 0);
    }
    control.peel_args[0].y = ctx.sphere_count();
    control.composite_args[0].y = 1;
    vkCmdUpdateBuffer(cmd, control_.get(), 0, sizeof control, &control);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                   VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
                       VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    // Nothing is carried between frames: every image starts undefined.
    for (const DeviceImage& image : images_)
        image_barrier(cmd, image.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    if (!options_.dual)
        image_barrier(cmd, depth_.get(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
}

// Peel pass `pass` and its composite, or (pass == geometry_passes_) the tail pass.
void PeelMethod::record_pass(VkCommandBuffer cmd, const FrameContext& ctx, int pass) {
    const bool tail = pass == geometry_passes_;
    const std::uint32_t p = std::uint32_t(pass);
    VkRenderingAttachmentInfo colors[2];
    std::uint32_t color_count = 0;
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    constexpr auto kClear = VK_ATTACHMENT_LOAD_OP_CLEAR, kAny = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    constexpr auto kStore = VK_ATTACHMENT_STORE_OP_STORE, kDrop = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    if (tail) {
        colors[color_count++] = attachment(images_[2].view(), kClear, kStore, clear_float(0, 0, 0, 0));
    } else if (options_.dual) {
        const VkClearValue nothing = clear_float(-INFINITY, -INFINITY, -INFINITY, -INFINITY);  // MAX identity
        colors[color_count++] = attachment(images_[1].view(), kClear, kStore, nothing);
        colors[color_count++] = attachment(images_[3].view(), p == 0 ? kAny : kClear, kStore, nothing);
    } else {
        // Pass p reads keys[p & 1] (what pass p-1 wrote) and writes keys[(p + 1) & 1].
        VkClearValue no_key{};
        for (int c = 0; c < 4; ++c) no_key.color.uint32[c] = kNoKey;
        colors[color_count++] = attachment(images_[(p + 1) & 1].view(), kClear, kStore, no_key);
        VkClearValue far{};
        far.depthStencil = {1.0f, 0};
        depth = attachment(depth_.view(), kClear, kDrop, far, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    }
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent_};
    info.layerCount = 1;
    info.colorAttachmentCount = color_count;
    info.pColorAttachments = colors;
    info.pDepthAttachment = (options_.dual || tail) ? nullptr : &depth;
    vkCmdBeginRendering(cmd, &info);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, tail ? tail_pipeline_ : peel_pipeline_);
    ctx.bind(cmd);
    set_viewport(cmd, extent_);
    if (!tail || options_.tail)  // without the tail option the layers beyond the passes are dropped
        vkCmdDrawIndirect(cmd, control_.get(), offsetof(PeelControl, peel_args) + p * sizeof(glm::uvec4), 1,
                          sizeof(glm::uvec4));
    vkCmdEndRendering(cmd);
    pass_barrier(cmd);
    if (tail) return;

    VkRenderingInfo composite{VK_STRUCTURE_TYPE_RENDERING_INFO};
    composite.renderArea = {{0, 0}, extent_};
    composite.layerCount = 1;
    vkCmdBeginRendering(cmd, &composite);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, composite_pipeline_);
    ctx.bind(cmd);
    set_viewport(cmd, extent_);
    vkCmdDrawIndirect(cmd, control_.get(), offsetof(PeelControl, composite_args) + p * sizeof(glm::uvec4), 1,
                      sizeof(glm::uvec4));
    vkCmdEndRendering(cmd);
    pass_barrier(cmd);
}

void PeelMethod::record_control_readback(VkCommandBuffer cmd) {
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy copy{0, 0, sizeof(PeelControl)};
    vkCmdCopyBuffer(cmd, control_.get(), control_readback_.get(), 1, &copy);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
}

void PeelMethod::record_finish(VkCommandBuffer cmd, const FrameContext& ctx) {
    record_pass(cmd, ctx, geometry_passes_);  // the tail (draws nothing unless layers remain somewhere)
    ctx.mark(cmd, "tail");
    ctx.resolve_to_hdr(cmd, resolve_pipeline_);
    ctx.mark(cmd, "resolve");
    record_control_readback(cmd);
}

void PeelMethod::prepare(FrameContext& ctx) {
    const Scene& scene = ctx.scene();
    if (options_.dual && scene.spheres.size() >= (1u << 24))
        throw std::invalid_argument("peel:dual handles fewer than 2^24 spheres (sphere indices travel as floats)");
    ensure_targets(ctx.extent());

    // Depth scale 2^-k with 2^k >= twice the farthest point of any sphere: every entry distance maps
    // into [0, 1/2] (the depth range), exactly.
    double reach = 0.0;
    for (const Sphere& s : scene.spheres)
        if (s.extinction > 0.0) reach = std::max(reach, glm::length(s.center - scene.camera.position) + s.radius);
    int exponent = 0;
    if (reach > 0.0 && std::isfinite(reach)) std::frexp(reach, &exponent);  // reach < 2^exponent
    exponent = std::clamp(exponent + 1, -100, 100);
    ctx.uniforms().params.y = float(std::ldexp(1.0, -exponent));

    info_ = PeelFrameInfo{};
    control_seen_ = PeelControl{};
    first_pass_ = 0;
    stopping_ = false;
}

// A step records up to passes_per_submit peel passes (the first also starts the frame), then either
// the tail and the resolve (the last pass, or the early stop) or a readback of the early-stop counts.
bool PeelMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int step) {
    if (stopping_) {
        record_finish(cmd, ctx);
        return true;
    }
    const int end = std::min(geometry_passes_, first_pass_ + options_.passes_per_submit);
    if (step == 0) record_start(cmd, ctx);
    for (int p = first_pass_; p < end; ++p) {
        record_pass(cmd, ctx, p);
        ctx.mark(cmd, options_.dual ? (p == 0 ? "window" : "dual[" + std::to_string(p) + "]")
                                    : "peel[" + std::to_string(p) + "]");
    }
    info_.passes_recorded = end;
    if (end == geometry_passes_) {
        record_finish(cmd, ctx);
        return true;
    }
    record_control_readback(cmd);
    return false;
}

GpuMethod::After PeelMethod::after_step(FrameContext&, int) {
    std::memcpy(&control_seen_, control_readback_.mapped(), sizeof control_seen_);
    if (stopping_ || info_.passes_recorded == geometry_passes_) {
        const PeelControl& control = control_seen_;
        for (int p = 0; p < info_.passes_recorded; ++p) {
            info_.pixels_going_on.push_back(control.going_on[p]);
            if (control.peel_args[p].y > 0) ++info_.passes_drawn;
        }
        info_.tail_drawn = options_.tail && control.peel_args[geometry_passes_].y > 0;
        return After::Done;
    }
    // Early stop: the last pass recorded left nothing to peel anywhere.
    if (control_seen_.going_on[info_.passes_recorded - 1] == 0) stopping_ = true;
    first_pass_ = info_.passes_recorded;
    return After::NextStep;
}

void PeelMethod::report(FrameStats& stats, const FrameContext& ctx) {
    // The frame path marked "clear+opaque", one pass per peel pass recorded, "tail", "resolve".
    const std::vector<PassTime> marked = std::move(stats.passes);
    const PeelControl& control = control_seen_;
    stats.passes = {marked[0]};
    double off = 0.0;
    for (int p = 0; p < info_.passes_recorded; ++p) {
        const PassTime& pass = marked[std::size_t(1 + p)];
        if (control.peel_args[p].y == 0)
            off += pass.ms;  // switched off on the GPU: only its clears ran
        else
            stats.passes.push_back(pass);
    }
    if (info_.passes_recorded > info_.passes_drawn) stats.passes.push_back({"passes switched off", off});
    stats.passes.push_back(marked[std::size_t(1 + info_.passes_recorded)]);
    stats.passes.push_back(marked[std::size_t(2 + info_.passes_recorded)]);
    const std::uint64_t pixels = std::uint64_t(ctx.extent().width) * ctx.extent().height;
    stats.memory_bytes = images_.size() * pixels * 16 + (options_.dual ? 0 : pixels * 4) + accum_.size() +
                         control_.size() + control_readback_.size();
}

}  // namespace brume
