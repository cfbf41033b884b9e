// Vulkan error handling: every call that returns VkResult goes through VK_CHECK, which throws a
// VulkanError naming the call and the result (so out-of-memory reaches the user as a message).
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace brume::vk {

class VulkanError : public std::runtime_error {
public:
    VulkanError(VkResult result, const std::string& what) : std::runtime_error(what), result_(result) {}
    VkResult result() const { return result_; }
    bool out_of_memory() const {
        return result_ == VK_ERROR_OUT_OF_DEVICE_MEMORY || result_ == VK_ERROR_OUT_OF_HOST_MEMORY;
    }

private:
    VkResult result_;
};

const char* result_name(VkResult result);
// What a user who ran out of memory should be told, for VK_ERROR_OUT_OF_DEVICE_MEMORY and
// VK_ERROR_OUT_OF_HOST_MEMORY (the raw call and source line mean nothing to someone who asked for a
// large frame); null for any other result.
const char* out_of_memory_advice(VkResult result);
[[noreturn]] void throw_vulkan_error(VkResult result, const char* call, const char* file, int line);

}  // namespace brume::vk

#define VK_CHECK(call)                                                                \
    do {                                                                              \
        VkResult vk_check_result_ = (call);                                           \
        if (vk_check_result_ != VK_SUCCESS)                                           \
            ::brume::vk::throw_vulkan_error(vk_check_result_, #call, __FILE__, __LINE__); \
    } while (0)
