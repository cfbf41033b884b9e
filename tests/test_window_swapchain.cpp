// Presentation to a real window: an X11 window (plain xcb, no toolkit) on the display that ctest
// starts with xvfb-run, a Vulkan surface and swapchain on it, frames presented through the frame
// path with two frames in flight, a resize that recreates the swapchain and a minimised window that
// skips frames. The validation layer is on; any message fails the test.
#include "gpu_test_env.h"
#include "test_scenes.h"

#include "render/frame/frame_path.h"
#include "render/frame/swapchain_presenter.h"
#include "render/methods/ppll.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"

#include <gtest/gtest.h>
#include <xcb/xcb.h>
#define VK_USE_PLATFORM_XCB_KHR
#include <vulkan/vulkan_xcb.h>

#include <cstdlib>
#include <memory>

namespace brume {
namespace {

using testing::small_scene;
using testing::sphere;

// One X window, mapped, of a given size.
class XcbWindow {
public:
    XcbWindow(std::uint16_t w, std::uint16_t h) {
        connection_ = xcb_connect(nullptr, nullptr);
        if (xcb_connection_has_error(connection_)) return;
        xcb_screen_t* screen = xcb_setup_roots_iterator(xcb_get_setup(connection_)).data;
        window_ = xcb_generate_id(connection_);
        xcb_create_window(connection_, XCB_COPY_FROM_PARENT, window_, screen->root, 0, 0, w, h, 0,
                          XCB_WINDOW_CLASS_INPUT_OUTPUT, screen->root_visual, 0, nullptr);
        xcb_map_window(connection_, window_);
        xcb_flush(connection_);
    }
    ~XcbWindow() {
        if (window_) xcb_destroy_window(connection_, window_);
        xcb_disconnect(connection_);
    }
    bool ok() const { return window_ != 0; }
    void resize(std::uint32_t w, std::uint32_t h) {
        const std::uint32_t size[] = {w, h};
        xcb_configure_window(connection_, window_, XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT, size);
        xcb_aux_sync();
    }
    VkSurfaceKHR make_surface(VkInstance instance) const {
        VkXcbSurfaceCreateInfoKHR info{VK_STRUCTURE_TYPE_XCB_SURFACE_CREATE_INFO_KHR};
        info.connection = connection_;
        info.window = window_;
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        vkCreateXcbSurfaceKHR(instance, &info, nullptr, &surface);
        return surface;
    }

private:
    void xcb_aux_sync() { free(xcb_get_input_focus_reply(connection_, xcb_get_input_focus(connection_), nullptr)); }

    xcb_connection_t* connection_ = nullptr;
    xcb_window_t window_ = 0;
};

TEST(WindowSwapchain, PresentsResizesAndSkipsMinimisedFrames) {
    ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
    XcbWindow window(48, 36);
    ASSERT_TRUE(window.ok()) << "no X display";

    testing::force_lavapipe();
    vk::DeviceOptions options;
    options.device_name = "lavapipe";
    options.validate = true;
    options.instance_extensions = {VK_KHR_SURFACE_EXTENSION_NAME, VK_KHR_XCB_SURFACE_EXTENSION_NAME};
    options.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    options.create_surface = [&](VkInstance instance) { return window.make_surface(instance); };
    vk::Device device(options);
    ASSERT_TRUE(device.surface());
    {
        Scene scene = small_scene(48, 36);
        scene.spheres.push_back(sphere({-0.3, 0.0, 0.0}, 0.8, 1.5));
        scene.spheres.push_back(sphere({0.3, 0.1, 0.2}, 0.7, 2.5, {0.3, 0.6, 0.9}));
        PpllMethod ppll(device);
        FramePath path(device);
        SwapchainPresenter presenter(device, {48, 36});
        ASSERT_TRUE(presenter.swapchain().valid());
        EXPECT_EQ(presenter.swapchain().extent().width, 48u);
        EXPECT_EQ(presenter.swapchain().extent().height, 36u);
        int shown = 0;
        for (int f = 0; f < 6; ++f) {
            scene.spheres[0].center.x = -0.3 + 0.05 * f;
            shown += path.render_to(presenter, ppll, scene);
        }
        EXPECT_EQ(shown, 6);

        // The window grows: the swapchain follows, and so does the frame.
        window.resize(64, 40);
        presenter.set_window_extent({64, 40});
        scene.camera.width = 64;
        scene.camera.height = 40;
        for (int f = 0; f < 3; ++f) path.render_to(presenter, ppll, scene);
        EXPECT_EQ(presenter.swapchain().extent().width, 64u);
        EXPECT_EQ(presenter.swapchain().extent().height, 40u);

        // Another method through the same path and window.
        auto soft = make_method(&device, "soft");
        EXPECT_TRUE(path.render_to(presenter, *soft->gpu(), scene));

        // Minimised (a zero framebuffer): no swapchain, frames are skipped; restored: shown again.
        presenter.set_window_extent({0, 0});
        EXPECT_FALSE(path.render_to(presenter, ppll, scene));
        EXPECT_FALSE(presenter.swapchain().valid());
        presenter.set_window_extent({64, 40});
        EXPECT_TRUE(path.render_to(presenter, ppll, scene));
    }
    const auto messages = device.take_validation_messages();
    for (const auto& m : messages) ADD_FAILURE() << m;
}

}  // namespace
}  // namespace brume
