// The main thread's side of the preview's frames: the last finished frame, an Image the render thread
// read back (app/preview_renderer.h), is uploaded once into an HDR image of its own and tone-mapped
// into the window with the panel over it, as often as the window is redrawn, while the render thread
// renders the next frame into its own targets. Its submissions go through a ring of its own, and
// ready() asks without waiting whether they are done, so the main loop never blocks on the GPU for
// it: on lavapipe the queue runs the render thread's submissions and these in turn, so a tone map
// submitted behind a slow frame's pass is done only after it; the main loop presents again, and
// queues the deferred present (SwapchainPresenter::set_deferred_present), once ready().
#pragma once

#include "render/frame/swapchain_presenter.h"
#include "render/image.h"
#include "render/vk/device.h"
#include "render/vk/frame_ring.h"
#include "render/vk/resources.h"

namespace brume::app {

class ImagePresenter {
public:
    explicit ImagePresenter(const vk::Device& device);
    // Waits for the device: the last present may still wait on the ring's semaphores.
    ~ImagePresenter();

    // The frame to show from now on; the next present() uploads it.
    void set_image(Image image);
    bool has_image() const { return extent_.width != 0 || pending_.width != 0; }
    // True when the last present's submission is done: present() will not wait.
    bool ready() const { return ring_.idle(); }
    // Uploads a new frame if there is one and presents the current one; as SwapchainPresenter::present.
    bool present(SwapchainPresenter& presenter);

private:
    const vk::Device& device_;
    vk::FrameRing ring_;
    vk::DeviceImage image_;
    vk::Buffer staging_;
    VkExtent2D extent_{};
    Image pending_;       // set, not yet copied into the staging buffer
    bool upload_ = false;  // the staging buffer holds a frame not yet copied into the image
};

}  // namespace brume::app
