#include "app/preview_session.h"

#include "app/cli_util.h"
#include "render/image_io.h"

#include <cmath>
#include <stdexcept>

namespace brume::app {

PreviewSession::PreviewSession(vk::Device& device, const Preset& preset, const std::string& method,
                               const MethodOptions& options, double exposure)
    : device_(device), options_(options), timeline_(preset), exposure_(exposure) {
    set_method(method);
    user_camera_ = timeline_.scene().camera;
}

void PreviewSession::replace_preset(const Preset& preset) {
    const int frame = timeline_.frame();
    timeline_ = PreviewTimeline(preset);
    timeline_.seek(frame);
}

void PreviewSession::set_method(const std::string& spec) {
    if (!find_method(spec).needs_device)
        throw std::invalid_argument("method '" + spec + "' runs on the CPU; the preview shows GPU methods "
                                    "(render it with brume play --method " + spec + ")");
    std::unique_ptr<Method> next = make_method(&device_, spec, options_);
    if (!next->gpu()) throw std::invalid_argument("method '" + spec + "' has no GPU frame path to preview");
    // The old method's buffers may only go once no frame that used them is still on the GPU.
    device_.wait_idle();
    method_ = std::move(next);
    method_spec_ = spec;
}

void PreviewSession::advance(double seconds) {
    if (!playback_.playing) return;
    if (playback_.one_frame_per_view) {
        playback_.pending_frames += 1.0;
    } else {
        playback_.pending_frames += seconds * timeline_.fps() * playback_.speed;
    }
    const int steps = int(std::floor(playback_.pending_frames));
    if (steps <= 0) return;
    playback_.pending_frames -= steps;
    int next = timeline_.frame() + steps;
    const int last = timeline_.frame_count() - 1;
    if (next > last) {
        if (playback_.loop) {
            next %= timeline_.frame_count();
        } else {
            next = last;
            playback_.playing = false;
        }
    }
    timeline_.seek(next);
}

Camera PreviewSession::camera() const { return follow_path_ ? timeline_.scene().camera : user_camera_; }

void PreviewSession::set_following_path(bool follow) {
    if (!follow && follow_path_) user_camera_ = camera();
    follow_path_ = follow;
}

void PreviewSession::set_user_camera(const Camera& camera) {
    user_camera_ = camera;
    follow_path_ = false;
}

Scene PreviewSession::scene(std::uint32_t width, std::uint32_t height) const {
    Scene scene = timeline_.scene();
    if (!follow_path_) scene.camera = user_camera_;
    scene.camera.width = int(width);
    scene.camera.height = int(height);
    return scene;
}

void PreviewSession::screenshot(FramePath& path, VkExtent2D viewport, const std::string& file) {
    if (viewport.width == 0 || viewport.height == 0)
        throw std::runtime_error("screenshot " + file + ": the window is minimised, there is no viewport");
    const Image image = path.render(method(), scene(viewport.width, viewport.height));
    refuse_non_finite(image, "the screenshot");
    if (file.ends_with(".exr"))
        write_exr(image, file);
    else
        write_png(image, file, exposure_);
}

}  // namespace brume::app
