#include "render/vk/device.h"

#include "render/vk/vk_check.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

namespace brume::vk {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

const char* type_name(VkPhysicalDeviceType type) {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete gpu";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated gpu";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual gpu";
    default: return "other";
    }
}

bool env_flag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

bool layer_available(const char* layer) {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, layer) == 0; });
}

VkInstance create_instance(bool validate, const std::vector<std::string>& wanted_extensions) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "brume";
    app.pEngineName = "brume";
    app.apiVersion = VK_API_VERSION_1_3;
    std::vector<const char*> layers, extensions;
    if (validate) {
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    for (const std::string& e : wanted_extensions) extensions.push_back(e.c_str());
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = std::uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = std::uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw VulkanError(r, "no Vulkan 1.3 driver found: install mesa-vulkan-drivers (lavapipe) or a GPU driver");
    if (r == VK_ERROR_EXTENSION_NOT_PRESENT) {
        std::string names;
        for (const std::string& e : wanted_extensions) names += " " + e;
        throw VulkanError(r, "the Vulkan instance lacks an extension the window needs:" + names);
    }
    VK_CHECK(r);
    return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
    std::uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

// "#0 'llvmpipe (...)'" for each of `indices`, as `brume devices` numbers them.
std::string numbered(const std::vector<std::string>& names, const std::vector<std::size_t>& indices) {
    std::string list;
    for (const std::size_t i : indices) list += std::string(list.empty() ? "" : ", ") + "#" + std::to_string(i) + " '" + names[i] + "'";
    return list;
}

VkPhysicalDevice choose_physical_device(VkInstance instance, const std::string& wanted) {
    std::vector<VkPhysicalDevice> devices = physical_devices(instance);
    if (devices.empty())
        throw VulkanError(VK_ERROR_INITIALIZATION_FAILED,
                          "no Vulkan device found: install mesa-vulkan-drivers (lavapipe) or a GPU driver");
    std::vector<std::string> names;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        names.emplace_back(p.deviceName);
    }
    return devices[pick_device(names, wanted)];
}

void require_capabilities(VkPhysicalDevice physical, const VkPhysicalDeviceProperties& props) {
    std::string missing;
    if (props.apiVersion < VK_API_VERSION_1_3) missing += " Vulkan 1.3;";
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroup};
    vkGetPhysicalDeviceProperties2(physical, &props2);
    if (!(subgroup.supportedStages & VK_SHADER_STAGE_FRAGMENT_BIT)) missing += " subgroup operations in fragment shaders;";
    const VkSubgroupFeatureFlags ops = VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    if ((subgroup.supportedOperations & ops) != ops) missing += " subgroup ballot and arithmetic;";
    VkPhysicalDeviceFeatures features;
    vkGetPhysicalDeviceFeatures(physical, &features);
    if (!features.fragmentStoresAndAtomics) missing += " fragmentStoresAndAtomics;";
    if (!props.limits.timestampComputeAndGraphics) missing += " timestamps;";
    if (!missing.empty())
        throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT,
                          std::string("device '") + props.deviceName + "' lacks what Brume needs:" + missing);
}

}  // namespace

bool device_name_matches(const std::string& device_name, const std::string& wanted) {
    const std::string name = lower(device_name);
    std::string needle = lower(wanted);
    if (needle == "lavapipe") needle = "llvmpipe";  // Mesa's CPU driver reports itself as llvmpipe
    return name.find(needle) != std::string::npos;
}

std::size_t pick_device(const std::vector<std::string>& names, const std::string& wanted) {
    std::vector<std::size_t> all(names.size());
    for (std::size_t i = 0; i < names.size(); ++i) all[i] = i;
    const std::string available = "; the devices (brume devices): " + (names.empty() ? std::string("none") : numbered(names, all));
    if (!wanted.empty() && wanted[0] == '#') {
        const std::string digits = wanted.substr(1);
        std::size_t index = names.size();
        if (!digits.empty() && digits.size() < 6 && std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            index = std::stoul(digits);
        if (index >= names.size())
            throw VulkanError(VK_ERROR_INITIALIZATION_FAILED, "no Vulkan device numbered '" + wanted + "'" + available);
        return index;
    }
    // Default: lavapipe, the device every test and figure is made on.
    std::vector<std::size_t> matches;
    for (std::size_t i = 0; i < names.size(); ++i)
        if (device_name_matches(names[i], wanted.empty() ? "lavapipe" : wanted)) matches.push_back(i);
    if (matches.empty()) {
        if (wanted.empty() && !names.empty()) return 0;  // no lavapipe here: take what there is
        throw VulkanError(VK_ERROR_INITIALIZATION_FAILED, "no Vulkan device matches '" + wanted + "'" + available);
    }
    for (const std::size_t i : matches)
        if (names[i] != names[matches.front()])
            throw VulkanError(VK_ERROR_INITIALIZATION_FAILED,
                              "--device '" + (wanted.empty() ? std::string("lavapipe") : wanted) + "' matches " +
                                  std::to_string(matches.size()) + " devices: " + numbered(names, matches) +
                                  "; name one more fully, or by its number (--device '#" +
                                  std::to_string(matches[1]) + "')");
    return matches.front();
}

std::vector<PhysicalDeviceInfo> Device::enumerate() {
    VkInstance instance = create_instance(false, {});
    std::vector<PhysicalDeviceInfo> out;
    for (VkPhysicalDevice d : physical_devices(instance)) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        out.push_back({p.deviceName, type_name(p.deviceType), p.apiVersion});
    }
    vkDestroyInstance(instance, nullptr);
    return out;
}

Device::Device(const DeviceOptions& options) {
    validation_enabled_ = options.validate || env_flag("BRUME_VALIDATE");
    if (validation_enabled_ && !layer_available(kValidationLayer))
        throw VulkanError(VK_ERROR_LAYER_NOT_PRESENT,
                          "validation requested but VK_LAYER_KHRONOS_validation is not installed "
                          "(Debian package vulkan-validationlayers)");
    instance_ = create_instance(validation_enabled_, options.instance_extensions);
    try {
        if (validation_enabled_) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            info.messageSeverity =
                VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            info.pfnUserCallback = &Device::on_debug_message;
            info.pUserData = this;
            VK_CHECK(create(instance_, &info, nullptr, &messenger_));
            set_object_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
                vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
        }

        if (options.create_surface) {
            surface_ = options.create_surface(instance_);
            if (!surface_) throw VulkanError(VK_ERROR_INITIALIZATION_FAILED, "the window's Vulkan surface could not be created");
        }
        physical_ = choose_physical_device(instance_, options.device_name);
        vkGetPhysicalDeviceProperties(physical_, &properties_);
        vkGetPhysicalDeviceMemoryProperties(physical_, &memory_properties_);
        require_capabilities(physical_, properties_);

        std::uint32_t family_count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, nullptr);
        std::vector<VkQueueFamilyProperties> families(family_count);
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, families.data());
        bool found = false;
        for (std::uint32_t i = 0; i < family_count && !found; ++i) {
            VkBool32 presents = VK_TRUE;
            if (surface_) VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(physical_, i, surface_, &presents));
            if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && families[i].timestampValidBits > 0 && presents) {
                queue_family_ = i;
                found = true;
            }
        }
        if (!found)
            throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT,
                              surface_ ? "device has no graphics queue with timestamps that can present to the window"
                                       : "device has no graphics queue with timestamps");

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queue_info.queueFamilyIndex = queue_family_;
        queue_info.queueCount = 1;
        queue_info.pQueuePriorities = &priority;

        VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        features13.dynamicRendering = VK_TRUE;
        features13.synchronization2 = VK_TRUE;
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features13};
        features.features.fragmentStoresAndAtomics = VK_TRUE;

        std::vector<const char*> device_extensions;
        for (const std::string& e : options.device_extensions) device_extensions.push_back(e.c_str());
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queue_info;
        info.enabledExtensionCount = std::uint32_t(device_extensions.size());
        info.ppEnabledExtensionNames = device_extensions.data();
        const VkResult created = vkCreateDevice(physical_, &info, nullptr, &device_);
        if (created == VK_ERROR_EXTENSION_NOT_PRESENT) {
            std::string names;
            for (const std::string& e : options.device_extensions) names += " " + e;
            throw VulkanError(created, std::string("device '") + properties_.deviceName + "' lacks an extension:" + names);
        }
        VK_CHECK(created);
        vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    } catch (...) {
        release();  // members are destroyed after this; release() leaves nothing for them to free twice
        throw;
    }
}

Device::~Device() { release(); }

void Device::release() {
    if (device_) {
        const auto queue_lock = lock_queue();
        vkDeviceWaitIdle(device_);
    }
    if (device_) vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
    if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(instance_, messenger_, nullptr);
        messenger_ = VK_NULL_HANDLE;
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
}

VkBool32 Device::on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                  VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                  void* user) {
    auto* self = static_cast<Device*>(user);
    std::string text = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "validation error: " : "validation warning: ";
    text += data && data->pMessage ? data->pMessage : "(no message)";
    std::lock_guard<std::mutex> lock(self->messages_mutex_);
    ++self->message_count_;
    if (self->messages_.size() < 64) self->messages_.push_back(std::move(text));
    return VK_FALSE;
}

std::size_t Device::validation_message_count() const {
    std::lock_guard<std::mutex> lock(messages_mutex_);
    return message_count_;
}

std::vector<std::string> Device::take_validation_messages() {
    std::lock_guard<std::mutex> lock(messages_mutex_);
    message_count_ = 0;
    return std::exchange(messages_, {});
}

void Device::set_name(VkObjectType type, std::uint64_t handle, const char* name) const {
    if (!set_object_name_) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    set_object_name_(device_, &info);
}

std::uint64_t Device::device_local_bytes() const {
    std::uint64_t best = 0;
    for (std::uint32_t i = 0; i < memory_properties_.memoryHeapCount; ++i)
        if (memory_properties_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            best = std::max<std::uint64_t>(best, memory_properties_.memoryHeaps[i].size);
    return best;
}

std::uint32_t Device::find_memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                       VkMemoryPropertyFlags preferred) const {
    for (int pass = 0; pass < 2; ++pass) {
        const VkMemoryPropertyFlags want = pass == 0 ? (required | preferred) : required;
        for (std::uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i)
            if ((type_bits & (1u << i)) && (memory_properties_.memoryTypes[i].propertyFlags & want) == want) return i;
    }
    throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, "no suitable Vulkan memory type");
}

void Device::wait_idle() const {
    const auto queue_lock = lock_queue();
    VK_CHECK(vkDeviceWaitIdle(device_));
}

}  // namespace brume::vk
