#include "render/vk/vk_check.h"

#include <cstdio>

namespace brume::vk {

const char* result_name(VkResult result) {
    switch (result) {
#define BRUME_RESULT(r) case r: return #r;
        BRUME_RESULT(VK_SUCCESS)
        BRUME_RESULT(VK_NOT_READY)
        BRUME_RESULT(VK_TIMEOUT)
        BRUME_RESULT(VK_INCOMPLETE)
        BRUME_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        BRUME_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        BRUME_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        BRUME_RESULT(VK_ERROR_DEVICE_LOST)
        BRUME_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        BRUME_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        BRUME_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        BRUME_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        BRUME_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        BRUME_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        BRUME_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        BRUME_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
        BRUME_RESULT(VK_ERROR_SURFACE_LOST_KHR)
        BRUME_RESULT(VK_ERROR_OUT_OF_DATE_KHR)
        BRUME_RESULT(VK_SUBOPTIMAL_KHR)
#undef BRUME_RESULT
    default: return "unknown VkResult";
    }
}

void throw_vulkan_error(VkResult result, const char* call, const char* file, int line) {
    char message[512];
    std::snprintf(message, sizeof message, "Vulkan call failed: %s returned %s (%s:%d)", call,
                  result_name(result), file, line);
    throw VulkanError(result, message);
}

}  // namespace brume::vk
