#include "app/preview_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <cstdlib>

namespace brume::app {
namespace {

std::string glfw_error() {
    const char* text = nullptr;
    glfwGetError(&text);
    return text ? text : "unknown GLFW error";
}

bool has_env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v;
}

}  // namespace

PreviewWindow::PreviewWindow(int width, int height, const std::string& title) {
    // GLFW's own message for a missing display is about X11 internals; a user needs to know what to do.
    // Debian 12's libglfw3 is GLFW's X11 build: a Wayland desktop is reached through XWayland, which sets
    // DISPLAY, so WAYLAND_DISPLAY alone is no display it can open.
    if (!has_env("DISPLAY"))
        throw PreviewUnavailable("no X11 display: set DISPLAY (a Wayland desktop's XWayland sets it), or use brume play");
    if (!glfwInit()) throw PreviewUnavailable("cannot open the display " +
                                              std::string(has_env("DISPLAY") ? std::getenv("DISPLAY") : "") + ": " +
                                              glfw_error() + " (check DISPLAY, or use brume play)");
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw PreviewUnavailable("GLFW finds no Vulkan loader that can present to a window (use brume play)");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        const std::string why = glfw_error();
        glfwTerminate();
        throw PreviewUnavailable("cannot create a window: " + why);
    }
    glfwSetWindowUserPointer(window_, this);
    // ImGui's GLFW backend chains to the callback installed before it, so the wheel reaches both.
    glfwSetScrollCallback(window_, &PreviewWindow::on_scroll);
    glfwSetKeyCallback(window_, &PreviewWindow::on_key);
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double, double) { on_event(w); });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int, int, int) { on_event(w); });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned) { on_event(w); });
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { on_event(w); });
    glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { on_event(w); });
}

void PreviewWindow::on_event(GLFWwindow* window) { ++static_cast<PreviewWindow*>(glfwGetWindowUserPointer(window))->events_; }

PreviewWindow::~PreviewWindow() {
    glfwDestroyWindow(window_);
    glfwTerminate();
}

void PreviewWindow::on_scroll(GLFWwindow* window, double, double y) {
    static_cast<PreviewWindow*>(glfwGetWindowUserPointer(window))->scroll_ += y;
    on_event(window);
}

void PreviewWindow::on_key(GLFWwindow* window, int key, int, int action, int) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        static_cast<PreviewWindow*>(glfwGetWindowUserPointer(window))->pressed_.push_back(key);
    on_event(window);
}

std::vector<std::string> PreviewWindow::required_instance_extensions() const {
    std::uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names && !glfwVulkanSupported())  // no loader, or a loader with no driver: say what to install, as render does
        throw PreviewUnavailable("no Vulkan driver found for the window: install mesa-vulkan-drivers (lavapipe) or a GPU driver");
    if (!names) throw PreviewUnavailable("GLFW knows no Vulkan surface extension for this display: " + glfw_error());
    return std::vector<std::string>(names, names + count);
}

VkSurfaceKHR PreviewWindow::create_surface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
    if (r != VK_SUCCESS)
        throw PreviewUnavailable("cannot create a Vulkan surface on the window (VkResult " + std::to_string(int(r)) +
                                 "): " + glfw_error());
    return surface;
}

VkExtent2D PreviewWindow::framebuffer_extent() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {std::uint32_t(w > 0 ? w : 0), std::uint32_t(h > 0 ? h : 0)};
}

void PreviewWindow::poll_events() const { glfwPollEvents(); }
void PreviewWindow::wait_events() const { glfwWaitEventsTimeout(0.1); }
void PreviewWindow::wait_events_for(double seconds) const {
    if (seconds > 0.0) glfwWaitEventsTimeout(seconds);
}
void PreviewWindow::wake() { glfwPostEmptyEvent(); }
bool PreviewWindow::should_close() const { return glfwWindowShouldClose(window_); }
void PreviewWindow::request_close() const { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void PreviewWindow::set_title(const std::string& title) const { glfwSetWindowTitle(window_, title.c_str()); }
void PreviewWindow::set_size(int width, int height) const { glfwSetWindowSize(window_, width, height); }
bool PreviewWindow::key_down(int glfw_key) const { return glfwGetKey(window_, glfw_key) == GLFW_PRESS; }

WindowInput PreviewWindow::take_input() {
    WindowInput in;
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window_, &x, &y);
    if (have_cursor_) {
        in.dx = x - last_x_;
        in.dy = y - last_y_;
    }
    last_x_ = x;
    last_y_ = y;
    have_cursor_ = true;
    in.scroll = scroll_;
    scroll_ = 0.0;
    in.pressed.swap(pressed_);
    in.left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    in.right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    in.middle = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
    in.shift = key_down(GLFW_KEY_LEFT_SHIFT) || key_down(GLFW_KEY_RIGHT_SHIFT);
    return in;
}

}  // namespace brume::app
