// The preview's window: GLFW with no client API, a Vulkan surface for the Device
// (DeviceOptions::create_surface), its framebuffer size, and the mouse and keys the camera reads.
// GLFW stays in app/: `render`, `play` and `bench` never touch it.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

struct GLFWwindow;

namespace brume::app {

// Why the preview cannot open a window (no display, GLFW or Vulkan cannot present): one line.
class PreviewUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Mouse motion and wheel since the last take_input(), in window pixels; buttons as held now.
struct WindowInput {
    double dx = 0.0, dy = 0.0;
    double scroll = 0.0;
    bool left = false, right = false, middle = false;
    bool shift = false;
    std::vector<int> pressed;  // GLFW keys pressed since the last take_input(), in order
};

class PreviewWindow {
public:
    // Throws PreviewUnavailable when there is no X11 or Wayland display or GLFW cannot start.
    PreviewWindow(int width, int height, const std::string& title);
    ~PreviewWindow();
    PreviewWindow(const PreviewWindow&) = delete;
    PreviewWindow& operator=(const PreviewWindow&) = delete;

    // The instance extensions a surface on this window needs.
    std::vector<std::string> required_instance_extensions() const;
    // For DeviceOptions::create_surface; throws PreviewUnavailable when Vulkan cannot present here.
    VkSurfaceKHR create_surface(VkInstance instance) const;

    // The framebuffer's size in pixels now; zero while minimised.
    VkExtent2D framebuffer_extent() const;
    void poll_events() const;
    // Blocks until an event arrives (a minimised window does no work), or 0.1 s.
    void wait_events() const;
    // Blocks until an event arrives or `seconds` pass.
    void wait_events_for(double seconds) const;
    // Ends a wait_events*() now; callable from any thread (the render thread, when a frame is done).
    static void wake();
    bool should_close() const;
    void request_close() const;
    void set_title(const std::string& title) const;
    void set_size(int width, int height) const;
    bool key_down(int glfw_key) const;
    WindowInput take_input();
    // Input and window events seen so far (a still window with no events needs no new frame).
    std::uint64_t event_count() const { return events_; }

    GLFWwindow* handle() const { return window_; }

private:
    static void on_scroll(GLFWwindow* window, double x, double y);
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void on_event(GLFWwindow* window);

    GLFWwindow* window_ = nullptr;
    double last_x_ = 0.0, last_y_ = 0.0;
    double scroll_ = 0.0;
    std::vector<int> pressed_;
    std::uint64_t events_ = 0;
    bool have_cursor_ = false;
};

}  // namespace brume::app
