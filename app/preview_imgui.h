// Dear ImGui's lifetime in the preview: the context, its GLFW backend (input) and its Vulkan
// backend, which 1.86 builds inside a VkRenderPass: the SwapchainPresenter's tone-map pass, so the
// UI is drawn over the frame in the same pass (SwapchainPresenter::set_overlay). It owns the
// descriptor pool the backend needs and uploads the font once.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <vulkan/vulkan.h>

struct GLFWwindow;

namespace brume::app {

class PreviewImgui {
public:
    // `render_pass`: the pass the UI is drawn in; `frames_in_flight`: how many recorded UI frames may
    // be in flight at once (the backend keeps one vertex buffer per frame).
    PreviewImgui(GLFWwindow* window, const vk::Device& device, VkRenderPass render_pass, std::uint32_t frames_in_flight);
    ~PreviewImgui();
    PreviewImgui(const PreviewImgui&) = delete;
    PreviewImgui& operator=(const PreviewImgui&) = delete;

    // Starts a UI frame: ImGui:: calls may follow until render().
    void new_frame();
    // Ends the UI frame; its draws are then recorded by record().
    void render();
    void record(VkCommandBuffer cmd);
    // Whether the UI wants the mouse or the keyboard now (then the camera leaves them alone).
    bool wants_mouse() const;
    bool wants_keyboard() const;

private:
    void upload_fonts();

    const vk::Device& device_;
    vk::UniqueDescriptorPool pool_;
    bool rendered_ = false;
};

}  // namespace brume::app
