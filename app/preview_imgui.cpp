#include "app/preview_imgui.h"

#include "render/vk/vk_check.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include <stdexcept>

namespace brume::app {
namespace {

void check_backend_result(VkResult r) {
    if (r != VK_SUCCESS) vk::throw_vulkan_error(r, "Dear ImGui's Vulkan backend", __FILE__, __LINE__);
}

}  // namespace

PreviewImgui::PreviewImgui(GLFWwindow* window, const vk::Device& device, VkRenderPass render_pass,
                           std::uint32_t frames_in_flight)
    : device_(device) {
    // The backend allocates one combined image sampler (the font) from this pool.
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool_info.maxSets = 4;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorPool(device.get(), &pool_info, nullptr, &pool));
    pool_ = vk::UniqueDescriptorPool(device.get(), pool);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForVulkan(window, true);

    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = device.instance();
    info.PhysicalDevice = device.physical();
    info.Device = device.get();
    info.QueueFamily = device.queue_family();
    info.Queue = device.queue();
    info.DescriptorPool = pool_;
    info.Subpass = 0;
    // The backend reuses a frame's vertex buffer after ImageCount frames: one more than can be in
    // flight keeps it from overwriting a buffer the GPU still reads.
    info.MinImageCount = 2;
    info.ImageCount = std::max<std::uint32_t>(frames_in_flight + 1, 2);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = &check_backend_result;
    if (!ImGui_ImplVulkan_Init(&info, render_pass)) throw std::runtime_error("Dear ImGui's Vulkan backend failed to start");
    upload_fonts();
}

PreviewImgui::~PreviewImgui() {
    device_.wait_idle();
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void PreviewImgui::upload_fonts() {
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.queueFamilyIndex = device_.queue_family();
    VkCommandPool raw_pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateCommandPool(device_.get(), &pool_info, nullptr, &raw_pool));
    const vk::UniqueCommandPool pool(device_.get(), raw_pool);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(device_.get(), &alloc, &cmd));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    ImGui_ImplVulkan_CreateFontsTexture(cmd);
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    {
        const auto queue_lock = device_.lock_queue();
        VK_CHECK(vkQueueSubmit(device_.queue(), 1, &submit, VK_NULL_HANDLE));
    }
    // Once, before the first frame: waiting for the whole device costs nothing here.
    device_.wait_idle();
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

void PreviewImgui::new_frame() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    rendered_ = false;
}

void PreviewImgui::render() {
    ImGui::Render();
    rendered_ = true;
}

void PreviewImgui::record(VkCommandBuffer cmd) {
    if (rendered_) ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
}

bool PreviewImgui::wants_mouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool PreviewImgui::wants_keyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace brume::app
