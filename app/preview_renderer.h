// The preview's render thread (docs/preview.md, "What runs beside the frame"): the frame path runs
// here, so the main thread keeps polling the window's events, drawing the panel and presenting the
// last finished frame while a slow frame renders.
//
// The main thread hands over what to render as a FrameRequest: the scene (built by the session on the
// main thread, so the timeline is never touched here), the methods as shared pointers (a method the
// session drops lives until the frame using it is done; the frame path waits for every method pass
// before it returns, so nothing of it is on the GPU when it goes), and the view's options. The thread
// owns its FramePath, and so the frame's targets, for good.
//
// Requests come in two kinds. The view: only the newest one is kept, a request not yet begun is
// replaced by the next (latest wins: orbiting or scrubbing during a slow frame renders the newest
// view next, never the ones in between); its result replaces a finished view not yet taken. Jobs (a
// screenshot, the reference's frame): each is rendered, before the next view, and kept until taken.
//
// A finished frame is handed back as an Image read back from the HDR target, not as the target: the
// thread may begin the next frame into its target at once, and the main thread presents the copy
// through its own upload (app/preview_image_presenter.h) with no GPU synchronisation between the
// two threads beyond the queue's lock (vk::Device::lock_queue). The cost is a readback and an upload
// of the internal-size frame, which the comparison views paid already.
//
// Test hook: BRUME_PREVIEW_SLOW_FRAME_MS=N makes the thread sleep N ms before each view it renders,
// as a slow frame would take (tests/preview_checks.sh checks that the window keeps presenting).
#pragma once

#include "app/preview_compare.h"
#include "render/frame/frame_path.h"
#include "render/frame/frame_stats.h"
#include "render/frame/list_heat_map.h"
#include "render/image.h"
#include "render/methods/method.h"
#include "render/vk/device.h"
#include "sim/scene.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace brume::app {

// One frame as the view shows it: the method's, or the comparison of two, with the heat map over it.
struct FrameRequest {
    Scene scene;  // at the size to render
    std::shared_ptr<Method> method;
    CompareMode compare = CompareMode::Off;
    std::shared_ptr<Method> compare_method;  // with compare != Off
    std::shared_ptr<ListHeatMap> heat_map;   // null: no heat map
    double exposure = 0.0;                   // the heat map's tint is divided by it
    bool list_stats = false;                 // the first method's list-length figures (extra atomics)
    bool want_stats = true;                  // fill RenderedFrame::stats
    int frame = 0;                           // the timeline's frame, handed back for the figures
};

struct RenderedFrame {
    std::uint64_t id = 0;
    int frame = 0;  // FrameRequest::frame
    Image image;
    FrameStats stats;         // the first method's
    ListLengthFigures heat;   // with a heat map
    double upload_ms = 0.0;   // the first method's scene upload (wall clock)
    double render_ms = 0.0;   // the rest of the frame's wall-clock time on the render thread
    std::string error;        // not empty: rendering threw this
    // The frame's scene cannot be rendered as asked (std::invalid_argument: a camera path through an
    // undefined view): an interactive window says why and keeps the last frame; anything else ends it.
    bool refused = false;
};

// Renders `request` through `path` (on the calling thread): what the render thread does for a frame.
RenderedFrame render_frame(FramePath& path, const FrameRequest& request);

class PreviewRenderer {
public:
    // `wake` is called on the render thread after each finished frame (the preview posts an empty
    // GLFW event, so a main loop waiting for events takes the frame at once).
    PreviewRenderer(vk::Device& device, std::function<void()> wake);
    // Finishes the frame being rendered, then stops the thread.
    ~PreviewRenderer();
    PreviewRenderer(const PreviewRenderer&) = delete;
    PreviewRenderer& operator=(const PreviewRenderer&) = delete;

    // The view to render next; replaces a view request not yet begun. Returns its id (increasing).
    std::uint64_t request_view(FrameRequest request);
    // A frame that must not be dropped; rendered before any view still waiting. Returns its id.
    std::uint64_t request_job(FrameRequest request);
    // The newest finished view not taken yet.
    std::optional<RenderedFrame> take_view();
    // The job `id` once it is finished (then it is forgotten).
    std::optional<RenderedFrame> take_job(std::uint64_t id);
    // A frame is being rendered or waits to be.
    bool busy() const;
    // Frames (views and jobs) rendered so far.
    std::uint64_t frames_rendered() const;

private:
    void loop();

    vk::Device& device_;
    std::function<void()> wake_;
    int slow_frame_ms_ = 0;  // the test hook above

    mutable std::mutex mutex_;
    std::condition_variable work_;
    bool stop_ = false;
    bool rendering_ = false;
    std::uint64_t next_id_ = 1;
    std::uint64_t rendered_ = 0;
    std::optional<std::pair<std::uint64_t, FrameRequest>> view_;  // waiting, latest wins
    std::deque<std::pair<std::uint64_t, FrameRequest>> jobs_;     // waiting, in order
    std::optional<RenderedFrame> finished_view_;
    std::map<std::uint64_t, RenderedFrame> finished_jobs_;
    std::thread thread_;  // last: it starts once everything above exists
};

}  // namespace brume::app
