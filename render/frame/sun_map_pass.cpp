#include "render/frame/sun_map_pass.h"

#include "sun_map_build.comp.h"
#include "render/vk/pipelines.h"
#include "render/vk/resources.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {

bool SunMapPass::wanted_on(const vk::Device& device) {
    if (const char* where = std::getenv("BRUME_SUN_MAP")) {
        const std::string w = where;
        if (w == "device") return true;
        if (w == "host") return false;
        throw std::invalid_argument("BRUME_SUN_MAP='" + w + "': 'device' or 'host'");
    }
    return device.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
}

SunMapPass::SunMapPass(const vk::Device& device, const vk::SharedDescriptors& descriptors)
    : device_(device),
      pipeline_(vk::create_compute_pipeline(device, descriptors.pipeline_layout(), "sun_map_build",
                                            BRUME_SPIRV(spv_sun_map_build_comp))) {}

bool SunMapPass::fits(const Scene& scene, const SunLight& sun, const SunDepthMap& map) const {
    const std::vector<std::uint32_t>& starts = sun.cell_start();
    std::uint64_t fullest = 0;
    for (std::size_t c = 0; c + 1 < starts.size(); ++c) fullest = std::max<std::uint64_t>(fullest, starts[c + 1] - starts[c]);
    // The largest radius in the lattice: the outsized spheres are in no cell (a lookup adds them).
    const std::vector<std::uint32_t>& outsized = sun.outsized_indices();
    double largest = 0.0;
    for (std::size_t k = 0, next = 0; k < scene.spheres.size(); ++k) {
        if (next < outsized.size() && outsized[next] == k) {
            ++next;
            continue;
        }
        largest = std::max(largest, scene.spheres[k].radius);
    }
    const double chord_cells = 2.0 * largest * map.inverse_cell() + 2.0;
    const double iterations = 2.0 * double(map.size_s()) + double(fullest) * (1.0 + chord_cells);
    const bool cpu_device = device_.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    return iterations <= (cpu_device ? 60000.0 : 1.0e6);
}

void SunMapPass::record(VkCommandBuffer cmd, const vk::SharedDescriptors& descriptors, const SunDepthMap& map) const {
    const std::uint64_t columns = std::uint64_t(map.size_u()) * std::uint64_t(map.size_v());
    // An invocation a column, 64 a group; the shader strides over any beyond the groups' limit.
    const std::uint32_t groups = std::uint32_t(std::min<std::uint64_t>(
        (columns + 63) / 64, std::min<std::uint64_t>(device_.properties().limits.maxComputeWorkGroupCount[0], 65535)));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    descriptors.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE);
    vkCmdDispatch(cmd, groups, 1, 1);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

}  // namespace brume
