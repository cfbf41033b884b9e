// The CPU particle simulator: a Preset's emitters, forces and obstacles stepped on a fixed clock.
//
// Clock. Step k ends at time k / (fps * substeps) seconds, computed from the integer k (no drift).
// Time 0 is the start of the simulation; the preroll is round(preroll * fps * substeps) steps
// simulated at construction, and frame f is the state after preroll + f * substeps steps, at time
// preroll_steps / (fps * substeps) + f / fps. Emitter times are on this clock.
//
// One step [t0, t1]: (1) every live particle is advanced by dt = t1 - t0 (sim/forces.h: exact for the
// linear part, turbulence frozen at t0), pushed out of the scene's boxes, and aged; (2) particles with
// age >= lifetime are removed, in index order by swap-and-pop; (3) births in (t0, t1] are added in
// emitter order, each emitter's bursts (by time) before its continuous particles, each advanced by
// its own age t1 - birth from its birth position (emitters.h), with the same field as the step, and
// pushed out of the boxes (one born inside a box it cannot leave dies at once). The state at time 0
// holds the births at times <= 0, at age 0.
//
// Budget (Timeline::max_particles). A birth finding the live count at the budget is skipped: it still
// takes its emission counter (so ids and every other particle stay the same), it is just never
// added. Deaths are removed before births, so a step's deaths free room for that step's births.
//
// Determinism. Single-threaded, counter-based randomness, fixed visiting order: the same preset
// gives bit-identical particles on the same build, and advance_to_frame(f) equals f step_frame()s.
#pragma once

#include "sim/forces.h"
#include "sim/particles.h"
#include "sim/preset.h"
#include "sim/scene.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {

// Thrown by a simulator whose stop flag was raised (Ctrl-C during a long preroll or replay).
class SimulationStopped : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Simulator {
public:
    // Throws std::invalid_argument for a timeline it cannot step (fps or substeps not positive,
    // preroll negative) or more than 65536 emitters (the id's emitter field). When `stop` is given,
    // every step checks it, and a raised flag ends the preroll or any stepping with SimulationStopped:
    // a preroll or replay can run for minutes, and a signal handler can only set a flag.
    explicit Simulator(const Preset& preset, const std::atomic<bool>* stop = nullptr);

    void step_frame();
    // Steps forward to frame f (f >= 0), replaying from the start if f is behind the current frame.
    void advance_to_frame(int frame);

    int frame() const;
    double time() const;  // seconds since the start of the simulation, preroll included
    double time_of_frame(int frame) const { return time_at(preroll_steps_ + std::uint64_t(frame) * substeps_); }  // time() there
    const Particles& particles() const { return particles_; }
    std::size_t size() const { return particles_.size(); }

    // The live particles as spheres with the age curves applied; those whose radius or extinction
    // comes out zero are skipped. Appends, so fixed scene spheres can already be in `out`.
    void append_spheres(std::vector<Sphere>& out) const;

    // Births so far per emitter (the emission counter, budget-skipped ones included), and births the
    // budget skipped in total.
    std::uint64_t emitted(std::size_t emitter) const { return emitters_[emitter].counter; }
    std::uint64_t skipped() const { return skipped_; }
    std::uint64_t step_index() const { return step_; }

    // An edit of emitter `e` alone: `next` is the current preset with only that emitter changed. While
    // neither the current emitter nor next's has emitted anything by now (no birth, none skipped by the
    // budget), the state is exactly what a fresh Simulator of `next` stepped to this frame would hold,
    // so the emitter can be swapped in place and the past kept (the preview's edits, whose frames before
    // the emitter's first birth stay valid). can_adopt_emitter says whether that holds.
    bool can_adopt_emitter(const Preset& next, std::size_t e) const;
    void adopt_emitter(const Preset& next, std::size_t e);
    double step_seconds() const { return 1.0 / steps_per_second_; }

private:
    struct EmitterState {
        std::vector<EmitterDesc::Burst> bursts;  // sorted by time (stable)
        std::uint64_t counter = 0;               // births so far, the id's low bits
        std::uint64_t continuous = 0;            // continuous births so far
    };

    void reset();
    void substep();
    // Births in (t_begin, t_end], or at times <= 0 for the initial state.
    void add_births(double t_begin, double t_end, bool initial);
    void birth(std::uint32_t emitter, double birth_time, double t_end, bool initial);
    // While the budget is full every birth is skipped (birth() counts it and draws nothing), so a run
    // of them is counted at once.
    bool budget_full() const { return particles_.size() >= preset_.timeline.max_particles; }
    void skip_births(std::uint32_t emitter, std::uint64_t count);
    void advance_new(std::size_t first);
    void remove_dead(std::size_t first);
    double time_at(std::uint64_t step) const { return double(step) / steps_per_second_; }

    void check_stop() const {
        if (stop_ && stop_->load(std::memory_order_relaxed))
            throw SimulationStopped("the simulation was stopped at step " + std::to_string(step_));
    }

    Preset preset_;
    const std::atomic<bool>* stop_ = nullptr;
    ForceField forces_;
    BoxObstacles obstacles_;
    double steps_per_second_ = 1.0;
    std::uint64_t substeps_ = 1;
    std::uint64_t preroll_steps_ = 0;

    Particles particles_;
    std::vector<EmitterState> emitters_;
    std::uint64_t step_ = 0;
    std::uint64_t skipped_ = 0;
    std::vector<float> phases_;     // the noise phases of the current step
    std::vector<double> new_ages_;  // age of each particle born in the current step
};

// Median wall-clock milliseconds per simulation step over `steps` steps, on this thread, for a fixed
// synthetic plume: `particles` live particles (one burst, lifetimes longer than the run), gravity,
// buoyancy, wind, drag, 2-octave turbulence and a ground box. Each timed step includes applying the
// age curves to every particle (append_spheres), so it is the cost of a frame with one substep.
double benchmark_step_ms(std::size_t particles, int steps);

}  // namespace brume
