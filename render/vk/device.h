// The Vulkan instance, physical device choice and logical device: headless by default, lavapipe
// unless another device is named, validation layers on request. A window asks for more through the
// options: instance and device extensions, and a surface whose presentation the chosen queue must
// support. One Device per process is typical; it owns everything it creates (the surface too) and
// holds no global state. Command buffers and submission live in the frame path (render/vk/frame_ring.h).
#pragma once

#include "render/vk/handle.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace brume::vk {

struct DeviceOptions {
    // Case-insensitive substring of the device name, or "lavapipe" (its driver reports itself as
    // "llvmpipe"); empty: lavapipe.
    std::string device_name;
    bool validate = false;    // Khronos validation layer on; also switched on by BRUME_VALIDATE=1
    std::vector<std::string> instance_extensions;  // beyond what Brume needs itself (a window's surface)
    std::vector<std::string> device_extensions;    // e.g. VK_KHR_swapchain
    // Called once the instance exists; the surface it returns is owned by the Device, and the queue
    // chosen must be able to present to it.
    std::function<VkSurfaceKHR(VkInstance)> create_surface;
};

// What `--device NAME` matches in a device name: "lavapipe" means Mesa's CPU driver, which names
// itself "llvmpipe (LLVM ...)"; any other name is matched as it is, case-insensitively.
bool device_name_matches(const std::string& device_name, const std::string& wanted);

// The device `--device` picks among `names` (in the order `brume devices` numbers them): "#N" the N-th;
// a name (device_name_matches) the one device it matches, or the first of several that share one name
// (two of the same GPU: "#1" picks the other); nothing (the default) the first lavapipe, else the first
// device. Throws VulkanError naming the devices when none matches or devices of different names do.
std::size_t pick_device(const std::vector<std::string>& names, const std::string& wanted);

struct PhysicalDeviceInfo {
    std::string name;
    std::string type;  // "cpu", "discrete gpu", ...
    std::uint32_t api_version = 0;
};

class Device {
public:
    explicit Device(const DeviceOptions& options = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    // Every device this loader can see (for `brume devices` and for error messages).
    static std::vector<PhysicalDeviceInfo> enumerate();

    VkInstance instance() const { return instance_; }
    VkDevice get() const { return device_; }
    VkPhysicalDevice physical() const { return physical_; }
    VkQueue queue() const { return queue_; }  // graphics, timestamps and (with a surface) present
    VkSurfaceKHR surface() const { return surface_; }  // null when headless
    std::uint32_t queue_family() const { return queue_family_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    const VkPhysicalDeviceMemoryProperties& memory_properties() const { return memory_properties_; }
    std::string name() const { return properties_.deviceName; }
    bool validation_enabled() const { return validation_enabled_; }
    // Bytes of the largest device-local heap.
    std::uint64_t device_local_bytes() const;

    // Validation messages (warnings and errors) seen since the device was created or last taken.
    std::size_t validation_message_count() const;
    std::vector<std::string> take_validation_messages();

    // Debug-utils object names, shown by validation messages and GPU debuggers.
    void set_name(VkObjectType type, std::uint64_t handle, const char* name) const;
    template <typename T>
    void set_name(VkObjectType type, T handle, const char* name) const {
        set_name(type, reinterpret_cast<std::uint64_t>(handle), name);
    }

    std::uint32_t find_memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                   VkMemoryPropertyFlags preferred = 0) const;

    // Waits until the device has finished everything submitted to it (under the queue's lock).
    void wait_idle() const;

    // The queue is externally synchronised (Vulkan: vkQueueSubmit*, vkQueuePresentKHR, vkQueueWaitIdle
    // and vkDeviceWaitIdle must not run at the same time on it from two threads). The preview renders
    // on one thread and presents on another, so every one of those calls in Brume holds this lock
    // (FrameRing::submit, Swapchain::present, wait_idle, the UI's font upload). It is recursive so
    // that a caller may hold it around a whole present (SwapchainPresenter's acquire, submit and
    // present) while the calls inside take it again.
    std::unique_lock<std::recursive_mutex> lock_queue() const { return std::unique_lock(queue_mutex_); }
    // As lock_queue(), without waiting: not owning the lock when another thread holds it (the preview's
    // main thread skips a present rather than wait for a frame's submission, which lavapipe runs
    // inside vkQueueSubmit).
    std::unique_lock<std::recursive_mutex> try_lock_queue() const {
        return std::unique_lock(queue_mutex_, std::try_to_lock);
    }

private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT types,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* user);
    void release();

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memory_properties_{};
    bool validation_enabled_ = false;
    PFN_vkSetDebugUtilsObjectNameEXT set_object_name_ = nullptr;

    mutable std::recursive_mutex queue_mutex_;
    mutable std::mutex messages_mutex_;
    std::vector<std::string> messages_;
    std::size_t message_count_ = 0;
};

}  // namespace brume::vk
