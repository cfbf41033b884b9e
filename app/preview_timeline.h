// The preview's timeline: random access to any frame of a preset by deterministic replay, with
// copies of the simulator's state (checkpoints) every few frames so that going backwards replays
// only from the nearest checkpoint. The simulator is deterministic (sim/simulator.h): a copy stepped
// forward equals a fresh simulator stepped to the same frame, so the frame shown after any scrub is
// the frame `brume play` renders.
#pragma once

#include "sim/preset.h"
#include "sim/scene.h"
#include "sim/simulator.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>

namespace brume::app {

class PreviewTimeline {
public:
    // `preset` as `brume play` uses it (size overridden, volumes prepared). Checkpoints are taken every
    // `checkpoint_every` frames while their particles fit in `checkpoint_budget_bytes`.
    explicit PreviewTimeline(const Preset& preset, int checkpoint_every = 8,
                             std::uint64_t checkpoint_budget_bytes = 512ull << 20);

    int frame_count() const { return preset_.timeline.frame_count(); }
    int frame() const { return sim_.frame(); }
    double time() const { return sim_.time(); }
    double fps() const { return preset_.timeline.fps; }
    // Frame `frame`, clamped to the preset's frames.
    void seek(int frame);
    // An edit the simulator does not read (lighting, camera, camera path, render settings, fixed
    // spheres, the duration): the new preset's scene from now on, and the simulated state and every
    // checkpoint stay, since the simulator would compute them again bit for bit. The caller
    // guarantees that `preset` differs from the current one only there (edit_affects_simulation).
    void replace_scene_keeping_simulation(const Preset& preset);
    // An edit of emitter `emitter` alone (`preset` differs from the current one only there): the
    // checkpoints from before either version of the emitter first emits are kept (Simulator::
    // adopt_emitter), the later ones dropped, and the current frame simulated again from the latest
    // kept one, whose frame it returns. Returns nullopt, changing nothing, when even frame 0 comes after
    // the emitter's first birth (an emitter that starts at once, or during the preroll): then only a
    // new timeline will do.
    std::optional<int> replace_emitter_keeping_past(const Preset& preset, std::size_t emitter);
    // The current frame's scene exactly as `brume play` builds it: the preset's scene, the live
    // particles as spheres after its fixed ones, the camera path's camera at this time, the
    // preset's resolution.
    Scene scene() const;
    std::size_t particles() const { return sim_.size(); }

    // The frames that have a checkpoint (frame 0 always has one), for marking the cached range.
    const std::map<int, Simulator>& checkpoints() const { return checkpoints_; }
    // The last frame simulated since the start: every frame up to it is at most
    // checkpoint_every - 1 steps away from a checkpoint.
    int simulated_until() const { return simulated_until_; }
    const Preset& preset() const { return preset_; }

private:
    void step_and_checkpoint();

    Preset preset_;
    Simulator sim_;
    std::map<int, Simulator> checkpoints_;
    int every_;
    std::uint64_t budget_bytes_;
    std::uint64_t checkpoint_bytes_ = 0;
    int simulated_until_ = 0;
};

}  // namespace brume::app
