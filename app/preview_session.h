// What the preview shows, apart from the window: the preset's timeline, playback, the camera (the
// preset's camera path, or the user's once they move it) and the method. It builds each frame's
// Scene the way `brume play` does, so a screenshot at the viewport's size is the frame `brume play
// --size` writes.
#pragma once

#include "app/preview_compare.h"
#include "app/preview_renderer.h"
#include "app/preview_timeline.h"
#include "render/frame/frame_path.h"
#include "render/frame/frame_stats.h"
#include "render/frame/list_heat_map.h"
#include "render/methods/method.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "sim/preset.h"

#include <memory>
#include <string>

namespace brume::app {

struct Playback {
    bool playing = false;
    bool loop = true;
    double speed = 1.0;             // times real time
    bool one_frame_per_view = false;  // scripted runs: one timeline frame per shown frame, whatever the clock
    double pending_frames = 0.0;    // timeline frames owed to the clock, not yet stepped
};

class PreviewSession {
public:
    // `preset` as `brume play` prepares it; `method`: a GPU method spec.
    PreviewSession(vk::Device& device, const Preset& preset, const std::string& method, const MethodOptions& options,
                   double exposure);

    PreviewTimeline& timeline() { return timeline_; }
    const PreviewTimeline& timeline() const { return timeline_; }
    Playback& playback() { return playback_; }
    // Advances playback by `seconds` of wall-clock time (or one frame in scripted runs); at the end
    // it loops or stops.
    void advance(double seconds);

    // A reloaded preset: a new timeline at the same frame (clamped to its frames); the method, the
    // user's camera and the exposure stay.
    void replace_preset(const Preset& preset);
    // An edit: as replace_preset, except that an edit the simulator does not read
    // (!edit_affects_simulation(key_path)) keeps the simulated frames and checkpoints, and an edit of
    // one emitter keeps those from before its first birth (PreviewTimeline::replace_emitter_keeping_past).
    void apply_edit(const Preset& preset, const std::string& key_path);
    // The frame the last edit's simulation replayed from: 0 from the start, -1 when it kept all.
    int last_edit_replayed_from() const { return last_edit_replayed_from_; }

    // Throws std::invalid_argument naming the method when it is unknown or has no GPU frame path.
    void set_method(const std::string& spec);
    const std::string& method_spec() const { return method_spec_; }
    GpuMethod& method() { return *method_->gpu(); }
    // Shared with the render thread, which keeps a method it renders with until that frame is done.
    const std::shared_ptr<Method>& shared_method() const { return method_; }

    // A second method beside or against the first (app/preview_compare.h); Off drops it. Throws
    // std::invalid_argument as set_method does.
    void set_comparison(const std::string& spec, CompareMode mode);
    CompareMode compare_mode() const { return compare_mode_; }
    const std::string& compare_spec() const { return compare_spec_; }
    GpuMethod& compare_method() { return *compare_method_->gpu(); }
    // The heat map of list length over the view (app/preview_heat_map.h); its figures are those of
    // the last frame shown that drew it (set_heat_figures).
    void set_heat_map(bool on);
    bool heat_map() const { return heat_map_on_; }
    const ListLengthFigures& heat_figures() const { return heat_figures_; }
    // What the render thread needs to render the current frame at width x height as the view shows it:
    // the method's, or the comparison, with the heat map over it when it is on (app/preview_renderer.h).
    FrameRequest frame_request(std::uint32_t width, std::uint32_t height, bool list_stats) const;
    // The heat map's figures of the last frame shown that drew it.
    void set_heat_figures(const ListLengthFigures& f) { heat_figures_ = f; }

    // Counts every change of what the render thread draws apart from the frame number (a new timeline,
    // an edit, the camera, the method, the comparison, the heat map, the exposure under the heat map):
    // the preview asks for a new frame when this or the frame changes.
    std::uint64_t view_generation() const { return view_generation_; }

    // The camera now: the camera path's (following) or the user's.
    Camera camera() const;
    bool following_path() const { return follow_path_; }
    void set_following_path(bool follow);
    // Replaces the camera with the user's (orbit, pan, zoom); stops following the path.
    void set_user_camera(const Camera& camera);
    void reset_camera() { set_following_path(true); }

    // The current frame at `width` x `height` with the current camera.
    Scene scene(std::uint32_t width, std::uint32_t height) const;
    double exposure() const { return exposure_; }
    void set_exposure(double stops) {
        // The tone map applies the exposure when the frame is presented; only the heat map's tint,
        // composed on the render thread, depends on it.
        if (stops != exposure_ && heat_map_on_) ++view_generation_;
        exposure_ = stops;
    }

    // Writes `image`, the current frame rendered at the viewport's size (frame_request): PNG as
    // `brume play` writes it (exposed sRGB), EXR linear. Throws ImageIoError and friends on failure.
    void write_screenshot(const Image& image, const std::string& file) const;

    FrameStats& last_stats() { return stats_; }

private:
    vk::Device& device_;
    MethodOptions options_;
    PreviewTimeline timeline_;
    Playback playback_;
    std::string method_spec_;
    // Shared pointers: the render thread holds the ones of the frame it renders (app/preview_renderer.h).
    std::shared_ptr<Method> method_;
    CompareMode compare_mode_ = CompareMode::Off;
    std::string compare_spec_;
    std::shared_ptr<Method> compare_method_;
    bool heat_map_on_ = false;
    std::shared_ptr<ListHeatMap> heat_map_;
    ListLengthFigures heat_figures_;
    bool follow_path_ = true;
    Camera user_camera_;
    double exposure_;
    FrameStats stats_;
    std::uint64_t view_generation_ = 0;
    int last_edit_replayed_from_ = -1;
};

}  // namespace brume::app
