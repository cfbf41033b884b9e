// Presents frames into a window: acquires a swapchain image, tone-maps the frame's HDR target into
// it (ToneMapPass, the PNG writer's transfer) with an optional overlay in the same render pass (the
// preview's UI), and queues it for presentation. Out-of-date swapchains and window resizes recreate
// the swapchain; a minimised window skips frames.
#pragma once

#include "render/frame/presenter.h"
#include "render/frame/tone_map.h"
#include "render/vk/resources.h"
#include "render/vk/swapchain.h"

#include <cstdint>

#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace brume {

class SwapchainPresenter : public Presenter {
public:
    SwapchainPresenter(const vk::Device& device, VkExtent2D window_extent);
    // Waits for the device: its last frames may still be on their way to the screen.
    ~SwapchainPresenter() override;

    // The window's framebuffer size now; a change recreates the swapchain before the next frame.
    void set_window_extent(VkExtent2D extent);
    void set_exposure(double stops) { exposure_stops_ = stops; }
    // Draws recorded inside the tone-map render pass, after the image (a UI).
    void set_overlay(std::function<void(VkCommandBuffer)> overlay) { overlay_ = std::move(overlay); }

    bool present(const FrameResources& frame, vk::FrameRing& ring) override;
    // As present(), for an HDR image other than a frame's target (the preview's side-by-side of two
    // methods), sampled in SHADER_READ_ONLY_OPTIMAL. Switching between views must wait for the device:
    // the tone-map pass has one descriptor set.
    bool present_view(VkImageView hdr, VkExtent2D hdr_extent, vk::FrameRing& ring);

    // Deferred presents (the preview's main thread, which must not wait for the queue): present()
    // submits the tone map and returns, and the queue present waits for present_deferred(), which the
    // caller makes once the submission is done (its ring's fence). On lavapipe vkQueuePresentKHR waits
    // for the queue to finish everything submitted before it, another thread's slow frame included;
    // after the tone map's fence it has nothing left to wait for. A frame that is captured is
    // presented at once.
    void set_deferred_present(bool deferred) { deferred_ = deferred; }
    bool has_deferred_present() const { return deferred_index_.has_value(); }
    // Queues the deferred present, if there is one. Returns whether there was.
    bool present_deferred();

    // Copies the next frame shown, overlay included, exactly as the window shows it. False when the
    // swapchain's images cannot be copied from (the surface does not allow it).
    bool capture_next_frame();
    // The copy, once a present() after capture_next_frame() returned true: RGBA, 8 bits a channel,
    // top row first, in `extent`. Empty before that; taking it clears it.
    std::vector<std::uint8_t> take_capture(VkExtent2D& extent);

    const vk::Swapchain& swapchain() const { return swapchain_; }
    VkRenderPass render_pass() const { return tone_map_->render_pass(); }

private:
    void ensure_targets();

    const vk::Device& device_;
    vk::Swapchain swapchain_;
    std::unique_ptr<ToneMapPass> tone_map_;
    std::vector<vk::UniqueFramebuffer> framebuffers_;
    std::uint64_t framebuffers_generation_ = ~0ull;
    VkExtent2D window_extent_;
    bool recreate_ = false;
    double exposure_stops_ = 0.0;
    std::function<void(VkCommandBuffer)> overlay_;
    bool deferred_ = false;
    std::optional<std::uint32_t> deferred_index_;
    VkSemaphore deferred_ready_ = VK_NULL_HANDLE;
    bool capture_requested_ = false;
    vk::Buffer capture_buffer_;
    std::vector<std::uint8_t> capture_;
    VkExtent2D capture_extent_{};
};

}  // namespace brume
