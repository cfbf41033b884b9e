#include "render/frame/gpu_method.h"

#include "render/frame/frame_path.h"

namespace brume {

void FrameContext::bind(VkCommandBuffer cmd) const { method_.descriptors().bind(cmd); }

void FrameContext::bind_compute(VkCommandBuffer cmd) const {
    method_.descriptors().bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE);
}

void FrameContext::draw_spheres(VkCommandBuffer cmd, VkPipeline pipeline) const {
    frame_.draw_spheres(cmd, pipeline, method_.descriptors());
}

void FrameContext::resolve_to_hdr(VkCommandBuffer cmd, VkPipeline pipeline) const {
    frame_.resolve_to_hdr(cmd, pipeline, method_.descriptors());
}

GpuMethod::GpuMethod(vk::Device& device) : device_(device), descriptors_(device) {}

GpuMethod::~GpuMethod() = default;

FramePath& GpuMethod::own_path() {
    if (!own_path_) own_path_ = std::make_unique<FramePath>(device_);
    return *own_path_;
}

Image GpuMethod::render(const Scene& scene, FrameStats* stats) { return own_path().render(*this, scene, stats); }

}  // namespace brume
