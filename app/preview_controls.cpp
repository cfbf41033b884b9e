#include "app/preview_controls.h"

#include "app/preview_camera.h"

#include <GLFW/glfw3.h>

#include <cmath>

namespace brume::app {
namespace {

constexpr double kOrbitDegPerPixel = 0.3;
constexpr double kOrbitKeyDegPerSecond = 60.0;
constexpr double kZoomPerWheelStep = 0.9;

}  // namespace

bool apply_controls(const WindowInput& in, bool mouse_taken, bool keyboard_taken, double seconds,
                    const PreviewWindow& window, PreviewSession& session) {
    bool moved = false;
    const VkExtent2D size = window.framebuffer_extent();
    if (!mouse_taken && size.height > 0) {
        if (in.left && !in.shift && (in.dx != 0.0 || in.dy != 0.0)) {
            // Dragging right turns the scene right: the eye goes left.
            session.set_user_camera(
                orbit_camera(session.camera(), -in.dx * kOrbitDegPerPixel, in.dy * kOrbitDegPerPixel));
            moved = true;
        }
        if ((in.right || in.middle || (in.left && in.shift)) && (in.dx != 0.0 || in.dy != 0.0)) {
            // The point under the cursor stays under it: the view moves by the drag's share of the height.
            session.set_user_camera(pan_camera(session.camera(), -in.dx / size.height, in.dy / size.height));
            moved = true;
        }
        if (in.scroll != 0.0) {
            session.set_user_camera(zoom_camera(session.camera(), std::pow(kZoomPerWheelStep, in.scroll)));
            moved = true;
        }
    }
    if (keyboard_taken) return moved;

    const double turn = kOrbitKeyDegPerSecond * seconds;
    const double yaw = (window.key_down(GLFW_KEY_LEFT) ? turn : 0.0) - (window.key_down(GLFW_KEY_RIGHT) ? turn : 0.0);
    const double pitch = (window.key_down(GLFW_KEY_UP) ? turn : 0.0) - (window.key_down(GLFW_KEY_DOWN) ? turn : 0.0);
    if (yaw != 0.0 || pitch != 0.0) {
        session.set_user_camera(orbit_camera(session.camera(), yaw, pitch));
        moved = true;
    }
    PreviewTimeline& timeline = session.timeline();
    Playback& playback = session.playback();
    for (int key : in.pressed) {
        switch (key) {
        case GLFW_KEY_SPACE: playback.playing = !playback.playing; break;
        case GLFW_KEY_COMMA: playback.playing = false; timeline.seek(timeline.frame() - 1); moved = true; break;
        case GLFW_KEY_PERIOD: playback.playing = false; timeline.seek(timeline.frame() + 1); moved = true; break;
        case GLFW_KEY_HOME: timeline.seek(0); moved = true; break;
        case GLFW_KEY_END: timeline.seek(timeline.frame_count() - 1); moved = true; break;
        case GLFW_KEY_R: session.reset_camera(); moved = true; break;
        case GLFW_KEY_EQUAL:
        case GLFW_KEY_KP_ADD: session.set_user_camera(zoom_camera(session.camera(), kZoomPerWheelStep)); moved = true; break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT: session.set_user_camera(zoom_camera(session.camera(), 1.0 / kZoomPerWheelStep)); moved = true; break;
        case GLFW_KEY_ESCAPE: window.request_close(); break;
        default: break;
        }
    }
    return moved;
}

}  // namespace brume::app
