#include "render/methods/kbuffer.h"

#include "fullscreen_ray.vert.h"
#include "kbuf_insert.frag.h"
#include "kbuf_resolve.frag.h"
#include "render/vk/pipelines.h"
#include "render/vk/vk_check.h"
#include "sphere_impostor.vert.h"

#include <stdexcept>

namespace brume {

using namespace vk;

namespace {

constexpr VkFormat kTailAccumFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kTailDepthFormat = VK_FORMAT_R32_SFLOAT;
constexpr std::uint32_t kEmpty = 0xffffffffu;

}  // namespace

std::uint32_t parse_kbuf_setting(const std::string& setting) {
    if (setting.empty()) return kKbufDefaultK;
    if (setting.size() > 3 || setting.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument("kbuf: k must be a whole number from 1 to " + std::to_string(kKbufMaxK) +
                                    " (got '" + setting + "')");
    const unsigned long k = std::stoul(setting);
    if (k < 1 || k > kKbufMaxK)
        throw std::invalid_argument("kbuf: k must be from 1 to " + std::to_string(kKbufMaxK) + " (got " + setting + ")");
    return std::uint32_t(k);
}

KBufferMethod::KBufferMethod(Device& device, std::uint32_t k)
    : GpuMethod(device), k_(k) {
    if (k < 1 || k > kKbufMaxK) throw std::invalid_argument("kbuf: k must be from 1 to " + std::to_string(kKbufMaxK));

    // Both insertion passes run the same shader (specialization constant 0: pass), so the two
    // compute bit-identical keys; both render into the tail targets, the key pass with writes off
    // (it only clears them).
    GraphicsPipelineDesc keys;
    keys.name = "kbuf_keys";
    keys.vertex = BRUME_SPIRV(spv_sphere_impostor_vert);
    keys.fragment = BRUME_SPIRV(spv_kbuf_insert_frag);
    keys.color_formats = {kTailAccumFormat, kTailDepthFormat};
    VkPipelineColorBlendAttachmentState no_writes = blend_none();
    no_writes.colorWriteMask = 0;
    keys.blends = {no_writes, no_writes};
    keys.fragment_constants = {0u, k};
    keys_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), keys);

    GraphicsPipelineDesc payload = keys;
    payload.name = "kbuf_payload";
    payload.blends = {blend_additive(), blend_additive()};
    payload.fragment_constants = {1u, k};
    payload_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), payload);

    GraphicsPipelineDesc resolve;
    resolve.name = "kbuf_resolve";
    resolve.vertex = BRUME_SPIRV(spv_fullscreen_ray_vert);
    resolve.fragment = BRUME_SPIRV(spv_kbuf_resolve_frag);
    resolve.color_formats = {FrameResources::kHdrFormat};
    resolve.fragment_constants = {k};
    resolve_pipeline_ = create_graphics_pipeline(device, descriptors_.pipeline_layout(), resolve);
}

void KBufferMethod::ensure_targets(VkExtent2D extent) {
    if (extent.width == extent_.width && extent.height == extent_.height) return;
    const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * k_ * sizeof(std::uint32_t);
    const VkDeviceSize range = device_.properties().limits.maxStorageBufferRange;
    if (bytes > range)
        throw std::runtime_error("kbuf:" + std::to_string(k_) + " at " + std::to_string(extent.width) + "x" +
                                 std::to_string(extent.height) + " needs slot buffers of " + format_bytes(bytes) +
                                 ", more than this device's " + format_bytes(range) +
                                 " storage-buffer limit; lower k or the resolution");
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    keys_ = Buffer(device_, bytes, usage, MemoryUse::Device, "kbuf.keys");
    ids_ = Buffer(device_, bytes, usage, MemoryUse::Device, "kbuf.ids");
    exits_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, "kbuf.exits");
    const VkImageUsageFlags target = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    tail_accum_ = DeviceImage(device_, kTailAccumFormat, extent, target, VK_IMAGE_ASPECT_COLOR_BIT, "kbuf.tail_accum");
    tail_optical_depth_ = DeviceImage(device_, kTailDepthFormat, extent, target, VK_IMAGE_ASPECT_COLOR_BIT,
                                      "kbuf.tail_optical_depth");
    descriptors_.write_storage(gpu::BINDING_KBUF_KEYS, keys_.get());
    descriptors_.write_storage(gpu::BINDING_KBUF_IDS, ids_.get());
    descriptors_.write_storage(gpu::BINDING_KBUF_EXITS, exits_.get());
    descriptors_.write_storage_image(gpu::BINDING_KBUF_TAIL_ACCUM, tail_accum_.view());
    descriptors_.write_storage_image(gpu::BINDING_KBUF_TAIL_OPTICAL_DEPTH, tail_optical_depth_.view());
    extent_ = extent;
}

bool KBufferMethod::record(VkCommandBuffer cmd, FrameContext& ctx, int) {
    // Empty slots, ordered before the key pass's atomics.
    vkCmdFillBuffer(cmd, keys_.get(), 0, VK_WHOLE_SIZE, kEmpty);
    vkCmdFillBuffer(cmd, ids_.get(), 0, VK_WHOLE_SIZE, kEmpty);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

    for (VkImage image : {tail_accum_.get(), tail_optical_depth_.get()})
        image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    auto insertion_pass = [&](VkPipeline pipeline, VkAttachmentLoadOp load) {
        begin_color_rendering(cmd, extent_, {tail_accum_.view(), tail_optical_depth_.view()}, load);
        ctx.draw_spheres(cmd, pipeline);
        vkCmdEndRendering(cmd);
    };
    insertion_pass(keys_pipeline_, VK_ATTACHMENT_LOAD_OP_CLEAR);  // also clears the tail targets
    ctx.mark(cmd, "keys");
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                       VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    insertion_pass(payload_pipeline_, VK_ATTACHMENT_LOAD_OP_LOAD);
    ctx.mark(cmd, "payload+tail");
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

    ctx.resolve_to_hdr(cmd, resolve_pipeline_);
    ctx.mark(cmd, "resolve");
    return true;
}

void KBufferMethod::prepare(FrameContext& ctx) { ensure_targets(ctx.extent()); }

void KBufferMethod::report(FrameStats& stats, const FrameContext&) {
    const std::uint64_t pixels = std::uint64_t(extent_.width) * extent_.height;
    stats.memory_bytes = keys_.size() + ids_.size() + exits_.size() + pixels * (16 + 4);
}

std::unique_ptr<Method> make_kbuf_method(Device& device, const std::string& setting) {
    return std::make_unique<KBufferMethod>(device, parse_kbuf_setting(setting));
}

}  // namespace brume
