#include "app/preview_renderer.h"

#include "app/preview_heat_map.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <string>
#include <utility>

namespace brume::app {

RenderedFrame render_frame(FramePath& path, const FrameRequest& request) {
    const auto start = std::chrono::steady_clock::now();
    RenderedFrame out;
    GpuMethod& method = *request.method->gpu();
    out.image = path.render(method, request.scene, request.want_stats ? &out.stats : nullptr, request.list_stats);
    out.upload_ms = path.last_upload_ms();
    if (request.compare != CompareMode::Off)
        out.image = compose_comparison(out.image, path.render(*request.compare_method->gpu(), request.scene),
                                       request.compare);
    if (request.heat_map) {
        const Image counts = path.render(*request.heat_map, request.scene);
        out.heat = list_length_figures(counts);
        out.image = overlay_list_heat_map(out.image, counts, out.heat.longest, request.exposure);
    }
    out.render_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() - out.upload_ms;
    return out;
}

PreviewRenderer::PreviewRenderer(vk::Device& device, std::function<void()> wake)
    : device_(device), wake_(std::move(wake)) {
    if (const char* slow = std::getenv("BRUME_PREVIEW_SLOW_FRAME_MS")) slow_frame_ms_ = std::max(0, std::atoi(slow));
    thread_ = std::thread([this] { loop(); });
}

PreviewRenderer::~PreviewRenderer() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    work_.notify_all();
    thread_.join();
}

std::uint64_t PreviewRenderer::request_view(FrameRequest request) {
    std::uint64_t id;
    {
        const std::lock_guard lock(mutex_);
        id = next_id_++;
        view_.emplace(id, std::move(request));  // a view still waiting is dropped: the newest wins
    }
    work_.notify_one();
    return id;
}

std::uint64_t PreviewRenderer::request_job(FrameRequest request) {
    std::uint64_t id;
    {
        const std::lock_guard lock(mutex_);
        id = next_id_++;
        jobs_.emplace_back(id, std::move(request));
    }
    work_.notify_one();
    return id;
}

std::optional<RenderedFrame> PreviewRenderer::take_view() {
    const std::lock_guard lock(mutex_);
    return std::exchange(finished_view_, std::nullopt);
}

std::optional<RenderedFrame> PreviewRenderer::take_job(std::uint64_t id) {
    const std::lock_guard lock(mutex_);
    const auto it = finished_jobs_.find(id);
    if (it == finished_jobs_.end()) return std::nullopt;
    RenderedFrame done = std::move(it->second);
    finished_jobs_.erase(it);
    return done;
}

bool PreviewRenderer::busy() const {
    const std::lock_guard lock(mutex_);
    return rendering_ || view_ || !jobs_.empty();
}

std::uint64_t PreviewRenderer::frames_rendered() const {
    const std::lock_guard lock(mutex_);
    return rendered_;
}

void PreviewRenderer::loop() {
    // Its own frame path: its ring, command pools and targets are used by this thread only.
    FramePath path(device_);
    std::unique_lock lock(mutex_);
    for (;;) {
        work_.wait(lock, [this] { return stop_ || view_ || !jobs_.empty(); });
        if (stop_) break;
        const bool job = !jobs_.empty();
        std::pair<std::uint64_t, FrameRequest> next;
        if (job) {
            next = std::move(jobs_.front());
            jobs_.pop_front();
        } else {
            next = std::move(*view_);
            view_.reset();
        }
        rendering_ = true;
        lock.unlock();

        RenderedFrame done;
        try {
            if (!job && slow_frame_ms_ > 0) std::this_thread::sleep_for(std::chrono::milliseconds(slow_frame_ms_));
            done = render_frame(path, next.second);
        } catch (const std::invalid_argument& e) {
            done.error = e.what();
            done.refused = true;
        } catch (const std::exception& e) {
            done.error = e.what();
        }
        done.id = next.first;
        done.frame = next.second.frame;
        next.second = {};  // the methods' last references may go here, with no pass of theirs in flight

        lock.lock();
        rendering_ = false;
        ++rendered_;
        if (job)
            finished_jobs_[done.id] = std::move(done);
        else
            finished_view_ = std::move(done);
        lock.unlock();
        wake_();
        lock.lock();
    }
}

}  // namespace brume::app
