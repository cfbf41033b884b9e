#include "render/vk/vk_check.h"

#include <cstdio>
#include <cstring>

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

const char* out_of_memory_advice(VkResult result) {
    if (result == VK_ERROR_OUT_OF_HOST_MEMORY)
        return "the Vulkan driver ran out of host memory: try a smaller --size or a smaller scene";
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY)
        return "the Vulkan device has too little memory for this frame's images and lists: try a smaller --size or "
               "a smaller scene";
    return nullptr;
}

void throw_vulkan_error(VkResult result, const char* call, const char* file, int line) {
    char message[512];
    if (const char* advice = out_of_memory_advice(result)) {
        // The advice first, for every path that shows only what() (the preview's render thread passes
        // its failures on as text); the call's name after it, without its arguments or source line.
        const std::size_t name = std::strcspn(call, "(");
        std::snprintf(message, sizeof message, "%s (%.*s returned %s)", advice, int(name), call, result_name(result));
    } else {
        std::snprintf(message, sizeof message, "Vulkan call failed: %s returned %s (%s:%d)", call, result_name(result),
                      file, line);
    }
    throw VulkanError(result, message);
}

}  // namespace brume::vk
