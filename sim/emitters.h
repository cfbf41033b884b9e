// Emitters (sim/preset.h EmitterDesc): where and when particles are born, with what velocity and
// properties, and how those properties change with age (AgeCurves).
//
// Timing. Continuous emission gives exactly floor(rate * (t - start)) particles by time t (t clamped
// to [start, stop]); particle n is born at start + (n + 1) / rate, the instant the count reaches n + 1.
// A burst is born at its time. The state at time t holds every birth at a time <= t; a birth at
// time b inside the step ending at t_end enters with age t_end - b and is advanced by that much, so
// a steady stream is as smooth as the emitter's rate, not clumped per step.
//
// Randomness. A particle is a pure function of (seed, emitter index, emission counter): counter-based
// draws (sim/rng.h), so nothing else (step size, budget, other emitters) changes it.
//
// Shapes. Point, Sphere (uniform in the ball), Box (uniform), Disc (uniform in area), and Density:
// in proportion to a density grid's trilinear field (sim/density_sampler.h), which must be loaded into
// EmitterDesc::density first (sim/vdb/emitter_densities.h).
#pragma once

#include "sim/particles.h"
#include "sim/preset.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace brume {

// Continuous births by time t: floor(rate * (clamp(t, start, stop) - start)). Rates and times come from
// decimal text, so rate * t can land a rounding error below an integer the user meant exactly (7.3 * 10
// in binary is just under 73): values within 1e-10 relative below an integer count as reaching it.
std::uint64_t continuous_count(const EmitterDesc& e, double t);

// Throws std::logic_error for a Density emitter whose sampler is null: a preset simulated without
// load_emitter_densities. The simulator checks every emitter up front, so the mistake shows at once.
void require_density_loaded(const EmitterDesc& e);

// Birth time of continuous particle n (from 0): start + (n + 1) / rate.
double continuous_birth_time(const EmitterDesc& e, std::uint64_t n);

// The particle born as emission number `counter` of emitter `emitter_index`, at age 0 at its birth
// position. `seed` is Timeline::seed.
Particle sample_particle(const EmitterDesc& e, std::uint64_t seed, std::uint32_t emitter_index,
                         std::uint64_t counter);

// The age curves at normalised age a (clamped to [0, 1]): factors on the base radius, extinction and
// albedo, exactly as commented in sim/preset.h.
struct AgeCurveFactors {
    double radius = 1.0;
    double extinction = 1.0;
    glm::dvec3 albedo{1.0};
    glm::dvec3 emission{1.0};
};
AgeCurveFactors evaluate_age_curves(const AgeCurves& curves, double a);

}  // namespace brume
