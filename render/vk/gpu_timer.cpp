#include "render/vk/gpu_timer.h"

#include "render/vk/vk_check.h"

namespace brume::vk {

GpuTimer::GpuTimer(const Device& device, std::uint32_t max_stamps, const char* name)
    : device_(device), max_stamps_(max_stamps), ns_per_tick_(device.properties().limits.timestampPeriod) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = max_stamps;
    VkQueryPool pool;
    VK_CHECK(vkCreateQueryPool(device.get(), &info, nullptr, &pool));
    pool_ = UniqueQueryPool(device.get(), pool);
    device.set_name(VK_OBJECT_TYPE_QUERY_POOL, pool, name);
    std::uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &family_count, families.data());
    const std::uint32_t bits = families[device.queue_family()].timestampValidBits;
    valid_mask_ = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
}

void GpuTimer::reset(VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, pool_, 0, max_stamps_); }

void GpuTimer::stamp(VkCommandBuffer cmd, std::uint32_t index) {
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_, index);
}

std::vector<double> GpuTimer::intervals_ms(std::uint32_t count) const {
    std::vector<std::uint64_t> ticks(count);
    VK_CHECK(vkGetQueryPoolResults(device_.get(), pool_, 0, count, count * sizeof(std::uint64_t), ticks.data(),
                                   sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    std::vector<double> ms;
    for (std::uint32_t i = 1; i < count; ++i)
        ms.push_back(double((ticks[i] - ticks[i - 1]) & valid_mask_) * ns_per_tick_ * 1e-6);
    return ms;
}

}  // namespace brume::vk
