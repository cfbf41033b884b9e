#include "app/preview_script_runner.h"

#include "app/preview_camera.h"
#include "app/preview_capture.h"
#include "app/preview_edit.h"
#include "app/preview_pending_edit.h"
#include "app/preview_reference.h"
#include "app/preview_reload.h"
#include "app/preview_renderer.h"
#include "app/preview_sequence.h"
#include "app/preview_session.h"
#include "app/preview_window.h"
#include "render/atomic_file.h"
#include "render/frame/swapchain_presenter.h"

#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

namespace brume::app {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

void ScriptRunner::frame_shown(SwapchainPresenter& presenter) {
    if (frames_to_wait_ > 0) --frames_to_wait_;
    if (capture_.path.empty()) return;
    VkExtent2D extent{};
    const std::vector<std::uint8_t> pixels = presenter.take_capture(extent);
    if (pixels.empty()) return;  // not this frame (an out-of-date swapchain): the next one
    try {
        write_capture_png(pixels, extent, capture_.path);
    } catch (const std::exception& e) {
        throw std::runtime_error(capture_.where + ": " + e.what());
    }
    std::printf("capture %s: the window at %ux%u\n", capture_.path.c_str(), extent.width, extent.height);
    std::fflush(stdout);
    capture_ = {};
}

bool ScriptRunner::run(ScriptTargets& targets) {
    if (reload_wait_.active) {
        if (targets.watcher->changes() == reload_wait_.seen) {
            if (seconds_since(reload_wait_.since) > 30.0)
                throw std::runtime_error(reload_wait_.where + ": wait-reload: " + targets.watcher->path().string() +
                                         " did not change within 30 s");
            return true;
        }
        reload_wait_.active = false;
    }
    if (screenshot_.id != 0) {
        std::optional<RenderedFrame> done = targets.renderer.take_job(screenshot_.id);
        if (!done) return true;
        const PendingScreenshot shot = std::exchange(screenshot_, {});
        try {
            if (!done->error.empty()) throw std::runtime_error(done->error);
            targets.session.write_screenshot(done->image, shot.path);
        } catch (const std::exception& e) {
            throw std::runtime_error(shot.where + ": " + e.what());
        }
        std::printf("%s", shot.line.c_str());
        if (shot.heat_map) {
            const ListLengthFigures& f = done->heat;
            std::printf(", heat map: longest %.17g, mean %.17g over %llu pixels, %llu nodes", f.longest, f.mean,
                        static_cast<unsigned long long>(f.nonempty_pixels), static_cast<unsigned long long>(f.total));
        }
        std::printf("\n");
        std::fflush(stdout);
    }
    if (reference_wait_) {
        if (targets.reference_busy()) return true;
        reference_wait_ = false;
        if (!targets.reference.error().empty())
            throw std::runtime_error(reference_where_ + ": reference-error: " + targets.reference.error());
        const ReferenceError& r = *targets.reference.last();
        std::printf("reference error: frame %d, method %s at %dx%d: max %.6g of peak, rmse %.6g of peak, "
                    "PSNR %.2f dB (reference %.2f s)\n",
                    r.frame, r.method.c_str(), r.width, r.height, r.max_of_peak, r.rmse_of_peak, r.psnr_db,
                    r.seconds);
        std::fflush(stdout);
    }
    if (edit_wait_) {
        if (targets.pending_edit.busy()) return true;
        edit_wait_ = false;
        if (!targets.pending_edit_error.empty())
            throw std::runtime_error(edit_where_ + ": set: " + targets.pending_edit_error);
        std::printf("set prepared: the view shows the edit\n");
        std::fflush(stdout);
    }
    if (sequence_wait_) {
        if (targets.sequence.running()) return true;
        sequence_wait_ = false;
        const SequenceRender& q = targets.sequence;
        if (q.status() != 0)
            throw std::runtime_error(sequence_where_ + ": render-sequence: brume play exited with status " +
                                     std::to_string(q.status()) + ": " + q.last_line());
        std::printf("render-sequence: %d of %d frames written by brume play: %s\n", q.frames_done(), q.frames_total(),
                    q.last_line().c_str());
        std::fflush(stdout);
    }
    while (frames_to_wait_ == 0 && capture_.path.empty() && !reload_wait_.active && !reference_wait_ &&
           !sequence_wait_ && !edit_wait_ && screenshot_.id == 0 && !commands_.empty()) {
        const ScriptCommand c = commands_.front();
        commands_.pop_front();
        try {
            if (!execute(c, targets)) return false;
        } catch (const std::exception& e) {
            throw std::runtime_error(c.where + ": " + e.what());
        }
    }
    return true;
}

bool ScriptRunner::execute(const ScriptCommand& c, ScriptTargets& targets) {
    PreviewSession& session = targets.session;
    const PreviewWindow& window = targets.window;
    PreviewTimeline& timeline = session.timeline();
    switch (c.kind) {
    case ScriptCommand::Kind::Frame:
        if (c.number >= timeline.frame_count())
            throw std::invalid_argument("frame " + std::to_string(c.number) + " is outside the preset's frames 0-" +
                                        std::to_string(timeline.frame_count() - 1));
        timeline.seek(int(c.number));
        break;
    case ScriptCommand::Kind::Play: session.playback().playing = true; break;
    case ScriptCommand::Kind::Pause: session.playback().playing = false; break;
    case ScriptCommand::Kind::Wait: frames_to_wait_ = c.number; break;
    case ScriptCommand::Kind::WaitReload:
        if (!targets.watcher) throw std::runtime_error("wait-reload: a built-in preset is not watched; open a file");
        reload_wait_ = {true, targets.watcher->changes(), Clock::now(), c.where};
        std::printf("waiting for %s to change\n", targets.watcher->path().string().c_str());
        break;
    case ScriptCommand::Kind::Set: {
        Preset edited = targets.editor->set(c.text, c.value);
        if (targets.submit_edit(std::move(edited), c.text)) {
            std::printf("set %s = %s (preparing on a worker)\n", c.text.c_str(), c.value.c_str());
            edit_wait_ = true;
            edit_where_ = c.where;
            targets.preset_edit_stale = true;
            break;
        }
        const int replayed_from = session.last_edit_replayed_from();
        std::printf("set %s = %s (%s)\n", c.text.c_str(), c.value.c_str(),
                    replayed_from == 0  ? "the simulation restarts from frame 0"
                    : replayed_from > 0 ? ("the simulation replays from frame " + std::to_string(replayed_from) +
                                           ", before the emitter's first birth; " +
                                           std::to_string(timeline.checkpoints().size()) + " checkpoints kept").c_str()
                                        : ("simulated frames kept: 0-" + std::to_string(timeline.simulated_until()) +
                                           ", " + std::to_string(timeline.checkpoints().size()) + " checkpoints").c_str());
        targets.preset_edit_stale = true;
        break;
    }
    case ScriptCommand::Kind::Save:
        targets.editor->save(c.text);
        std::printf("saved %s\n", c.text.c_str());
        break;
    case ScriptCommand::Kind::Orbit: session.set_user_camera(orbit_camera(session.camera(), c.x, c.y)); break;
    case ScriptCommand::Kind::Method: session.set_method(c.text); break;
    case ScriptCommand::Kind::Compare:
        session.set_comparison(c.text, c.number == 0   ? CompareMode::Off
                                       : c.number == 1 ? CompareMode::Split
                                                       : CompareMode::Difference);
        break;
    case ScriptCommand::Kind::Resize:
        window.set_size(int(c.number), int(c.number2));
        frames_to_wait_ = 1;  // the next frame is shown at the new size
        break;
    case ScriptCommand::Kind::Screenshot: {
        // The frame of the state the script has set, at the viewport's size, rendered on the render
        // thread as a job (never dropped for a newer view); the script waits for it.
        const VkExtent2D viewport = window.framebuffer_extent();
        if (viewport.width == 0 || viewport.height == 0)
            throw std::runtime_error("screenshot " + c.text + ": the window is minimised, there is no viewport");
        FrameRequest request = session.frame_request(viewport.width, viewport.height, true);
        request.want_stats = false;
        char line[512];
        std::snprintf(line, sizeof line, "screenshot %s: frame %d at %ux%u, method %s", c.text.c_str(),
                      timeline.frame(), viewport.width, viewport.height, session.method_spec().c_str());
        screenshot_ = {targets.renderer.request_job(std::move(request)), c.text, c.where, line, session.heat_map()};
        break;
    }
    case ScriptCommand::Kind::Capture: {
        check_writable_path(c.text);
        const vk::Swapchain& swapchain = targets.presenter.swapchain();
        if (swapchain.valid() && !swapchain.can_copy())
            throw std::runtime_error("capture: this window's swapchain images cannot be copied from");
        capture_.path = c.text;
        capture_.where = c.where;
        break;
    }
    case ScriptCommand::Kind::ReferenceError:
        targets.start_reference();
        reference_wait_ = true;
        reference_where_ = c.where;
        break;
    case ScriptCommand::Kind::Panel: targets.panel_visible = c.number != 0; break;
    case ScriptCommand::Kind::HeatMap: session.set_heat_map(c.number != 0); break;
    case ScriptCommand::Kind::RenderSequence:
        if (c.number2 >= timeline.frame_count())
            throw std::invalid_argument("render-sequence: frame " + std::to_string(c.number2) +
                                        " is outside the preset's frames 0-" + std::to_string(timeline.frame_count() - 1));
        targets.start_sequence(c.text, int(c.number), int(c.number2), "png");
        sequence_wait_ = true;
        sequence_where_ = c.where;
        std::printf("render-sequence %s: frames %lld-%lld started\n", c.text.c_str(), c.number, c.number2);
        std::fflush(stdout);  // a log being followed shows the start while the sequence runs
        break;
    case ScriptCommand::Kind::Camera: {
        const Camera cam = session.camera();
        std::printf("camera position %.17g %.17g %.17g look_at %.17g %.17g %.17g\n", cam.position.x, cam.position.y,
                    cam.position.z, cam.look_at.x, cam.look_at.y, cam.look_at.z);
        break;
    }
    case ScriptCommand::Kind::Quit: return false;
    }
    std::fflush(stdout);
    return true;
}

}  // namespace brume::app
