#include "app/preview_session.h"

#include "app/cli_util.h"
#include "app/preview_edit.h"
#include "app/preview_heat_map.h"
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
    ++view_generation_;
}

void PreviewSession::apply_edit(const Preset& preset, const std::string& key_path) {
    if (edit_affects_simulation(key_path)) {
        // An emitter edit keeps the frames before that emitter's first birth; anything else the
        // simulator reads replays it from the start.
        const std::optional<std::size_t> emitter = edited_emitter(key_path);
        const std::optional<int> from = emitter ? timeline_.replace_emitter_keeping_past(preset, *emitter) : std::nullopt;
        if (from) {
            ++view_generation_;
            last_edit_replayed_from_ = *from;
            return;
        }
        replace_preset(preset);
        last_edit_replayed_from_ = 0;
        return;
    }
    timeline_.replace_scene_keeping_simulation(preset);
    ++view_generation_;
    last_edit_replayed_from_ = -1;
}

namespace {

// A GPU method of the registry, or std::invalid_argument naming why not.
std::unique_ptr<Method> make_gpu_method(vk::Device& device, const std::string& spec, const MethodOptions& options) {
    if (!find_method(spec).needs_device)
        throw std::invalid_argument("method '" + spec + "' runs on the CPU; the preview shows GPU methods "
                                    "(render it with brume play --method " + spec + ")");
    std::unique_ptr<Method> next = make_method(&device, spec, options);
    if (!next->gpu()) throw std::invalid_argument("method '" + spec + "' has no GPU frame path to preview");
    return next;
}

}  // namespace

void PreviewSession::set_comparison(const std::string& spec, CompareMode mode) {
    std::shared_ptr<Method> next = mode == CompareMode::Off ? nullptr : make_gpu_method(device_, spec, options_);
    // No wait for the device: a frame still rendering with the old method holds it (FrameRequest).
    compare_method_ = std::move(next);
    ++view_generation_;
    compare_mode_ = mode;
    compare_spec_ = mode == CompareMode::Off ? "" : spec;
}

FrameRequest PreviewSession::frame_request(std::uint32_t width, std::uint32_t height, bool list_stats) const {
    FrameRequest r;
    r.scene = scene(width, height);
    r.method = method_;
    r.compare = compare_mode_;
    if (compare_mode_ != CompareMode::Off) r.compare_method = compare_method_;
    if (heat_map_on_) r.heat_map = heat_map_;
    r.exposure = exposure_;
    r.list_stats = list_stats;
    return r;
}

void PreviewSession::set_heat_map(bool on) {
    if (on && !heat_map_) heat_map_ = std::make_shared<ListHeatMap>(device_);
    if (on != heat_map_on_) ++view_generation_;
    heat_map_on_ = on;
    if (!on) heat_figures_ = {};
}

void PreviewSession::set_method(const std::string& spec) {
    std::shared_ptr<Method> next = make_gpu_method(device_, spec, options_);
    // The old method's buffers may only go once no frame that used them is still on the GPU: a frame
    // rendering with it holds it (FrameRequest), and the frame path waits for every method pass
    // before it returns, so the last reference goes with nothing of it in flight.
    method_ = std::move(next);
    method_spec_ = spec;
    ++view_generation_;
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
    if (follow != follow_path_) ++view_generation_;
    follow_path_ = follow;
}

void PreviewSession::set_user_camera(const Camera& camera) {
    user_camera_ = camera;
    follow_path_ = false;
    ++view_generation_;
}

Scene PreviewSession::scene(std::uint32_t width, std::uint32_t height) const {
    Scene scene = timeline_.scene();
    if (!follow_path_) scene.camera = user_camera_;
    scene.camera.width = int(width);
    scene.camera.height = int(height);
    return scene;
}

void PreviewSession::write_screenshot(const Image& image, const std::string& file) const {
    refuse_non_finite(image, "the screenshot");
    if (file.ends_with(".exr"))
        write_exr(image, file);
    else
        write_png(image, file, exposure_);
}

}  // namespace brume::app
