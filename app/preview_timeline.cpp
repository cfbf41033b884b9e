#include "app/preview_timeline.h"

#include "sim/camera_path.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace brume::app {
namespace {

// What one live particle costs in a checkpoint: fourteen floats, its emitter and its id (sim/particles.h).
constexpr std::uint64_t kParticleBytes = 15 * sizeof(float) + 2 * sizeof(double) + sizeof(std::uint32_t) + sizeof(std::uint64_t);

}  // namespace

PreviewTimeline::PreviewTimeline(const Preset& preset, int checkpoint_every, std::uint64_t checkpoint_budget_bytes)
    : preset_(preset), sim_(preset_), every_(checkpoint_every), budget_bytes_(checkpoint_budget_bytes) {
    if (every_ < 1) throw std::invalid_argument("checkpoint interval must be at least 1 frame");
    if (frame_count() < 1) throw std::invalid_argument(preset_.name + ": the timeline has no frames");
    checkpoints_.emplace(0, sim_);
}

void PreviewTimeline::step_and_checkpoint() {
    sim_.step_frame();
    const int f = sim_.frame();
    simulated_until_ = std::max(simulated_until_, f);
    if (f % every_ != 0 || checkpoints_.count(f)) return;
    // A checkpoint holds a copy of every live particle; past the budget, scrubbing replays further.
    const std::uint64_t bytes = std::uint64_t(sim_.size()) * kParticleBytes;
    if (checkpoint_bytes_ + bytes > budget_bytes_) return;
    checkpoint_bytes_ += bytes;
    checkpoints_.emplace(f, sim_);
}

void PreviewTimeline::seek(int frame) {
    frame = std::clamp(frame, 0, frame_count() - 1);
    if (frame == sim_.frame()) return;
    // Backwards, or forwards past a checkpoint nearer than the current frame: start from the nearest
    // checkpoint at or before the target.
    auto at = checkpoints_.upper_bound(frame);
    --at;  // frame 0 is always there
    if (frame < sim_.frame() || at->first > sim_.frame()) sim_ = at->second;
    while (sim_.frame() < frame) step_and_checkpoint();
}

void PreviewTimeline::replace_scene_keeping_simulation(const Preset& preset) {
    preset_ = preset;
    if (frame_count() < 1) throw std::invalid_argument(preset_.name + ": the timeline has no frames");
    // A shorter duration: the frames past the new end are no longer reachable.
    simulated_until_ = std::min(simulated_until_, frame_count() - 1);
    if (sim_.frame() > frame_count() - 1) seek(frame_count() - 1);
}

std::optional<int> PreviewTimeline::replace_emitter_keeping_past(const Preset& preset, std::size_t emitter) {
    // Checkpoints are in frame order, and an emitter that has not emitted by a frame has not emitted by
    // any earlier one: the kept ones are a prefix.
    auto keep_end = checkpoints_.begin();
    while (keep_end != checkpoints_.end() && keep_end->second.can_adopt_emitter(preset, emitter)) ++keep_end;
    if (keep_end == checkpoints_.begin()) return std::nullopt;
    const int frame = sim_.frame();
    checkpoints_.erase(keep_end, checkpoints_.end());
    checkpoint_bytes_ = 0;
    for (auto& [f, checkpoint] : checkpoints_) {
        checkpoint.adopt_emitter(preset, emitter);
        if (f != 0) checkpoint_bytes_ += std::uint64_t(checkpoint.size()) * kParticleBytes;
    }
    preset_ = preset;
    sim_ = std::prev(checkpoints_.end())->second;
    const int from = sim_.frame();
    simulated_until_ = from;
    seek(frame);
    return from;
}

Scene PreviewTimeline::scene() const {
    Scene scene = preset_.scene;
    sim_.append_spheres(scene.spheres);
    scene.camera = camera_on_path(preset_, sim_.time());  // an undefined view: the frame's error, shown
    scene.camera.width = preset_.scene.camera.width;
    scene.camera.height = preset_.scene.camera.height;
    return scene;
}

}  // namespace brume::app
