// Forces (sim/preset.h ForceDesc), the integrator, and collisions with the scene's opaque boxes.
//
// Every force is linear in the velocity, so the acceleration splits as a(x, v, t) = b(x, t) - k v:
//   k     = sum of drag strengths + sum of wind strengths            (one number for the whole preset)
//   b     = gravity + buoyancy * (0, 1, 0) + sum of wind strength * wind velocity
//           + turbulence(x, t) + vortices(x)
// A step of length dt freezes b at the step's start (position and time) and integrates the linear
// part exactly (an exponential Euler step):
//   v' = v e + b phi1,   x' = x + v phi1 + b phi2,   e = exp(-k dt), phi1 = (1 - e) / k,
//   phi2 = (dt - phi1) / k.
// So constant accelerations (gravity, buoyancy), drag and wind relaxation are integrated exactly,
// whatever the step, and the scheme is stable for any k >= 0; only the position dependence of
// turbulence and vortices is first order in dt.
#pragma once

#include "sim/noise.h"
#include "sim/preset.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace brume {

// Coefficients of one exponential Euler step (see above), rounded to float for the particle loop.
struct LinearStep {
    float decay = 1.0f;  // e
    float phi1 = 0.0f;
    float phi2 = 0.0f;
};
// Computed in double without cancellation as k dt -> 0 (phi1 -> dt, phi2 -> dt^2 / 2).
LinearStep make_linear_step(double k, double dt);

class ForceField {
public:
    ForceField() = default;
    // `seed` (Timeline::seed) and each force's index pick that force's turbulence modes.
    ForceField(const std::vector<ForceDesc>& forces, std::uint64_t seed);

    double linear_rate() const { return k_; }  // k
    LinearStep linear_step(double dt) const { return make_linear_step(k_, dt); }

    // Noise phases at time t, one per mode of every turbulence force: computed once per step.
    std::size_t phase_count() const { return phase_count_; }
    void phases(double t, float* out) const;

    // b(x_i) for n particles, written to ax/ay/az (`phases` from phases()). Arrays must not alias.
    void accelerations(const float* x, const float* y, const float* z, std::size_t n, const float* phases,
                       float* ax, float* ay, float* az) const;

    // The full a(x, v, t) in double precision (turbulence with std::cos), for tests and tools.
    glm::dvec3 acceleration(const glm::dvec3& x, const glm::dvec3& v, double t) const;

private:
    struct Turbulence {
        CurlNoise noise;   // strength and scale already folded in
        double speed = 0;  // noise time per second
    };
    struct Vortex {
        glm::dvec3 center{0.0};
        glm::dvec3 axis{0.0, 1.0, 0.0};  // unit
        double strength = 0.0;
        double radius2 = 1.0;
    };
    glm::dvec3 constant_{0.0};
    double k_ = 0.0;
    std::vector<Turbulence> turbulence_;
    std::vector<Vortex> vortices_;
    std::size_t phase_count_ = 0;
};

// One step for n particles: v' = v e + a phi1, x' = x + v phi1 + a phi2 (a from accelerations()). The
// position is x + x_lo (sim/particles.h): each move is added as a compensated sum, so moves far below
// x's float step still add up.
void integrate(const LinearStep& step, const float* ax, const float* ay, const float* az, std::size_t n,
               float* x, float* y, float* z, float* x_lo, float* y_lo, float* z_lo, float* vx, float* vy, float* vz);

// The scene's opaque boxes as obstacles. A centre strictly inside a box (min < p < max on every axis)
// is pushed out through the nearest face (ties: x before y before z, min before max; a face whose
// exit point lies inside another box is passed over for the next nearest) onto the face itself, and
// its velocity component into that face is removed (no friction: ForceDesc has no
// parameter for it, and smoke slides). Box bounds are rounded outward to float once, so "inside" for
// a float position means exactly what it means for the double box.
class BoxObstacles {
public:
    BoxObstacles() = default;
    explicit BoxObstacles(const std::vector<Box>& boxes);

    bool empty() const { return boxes_.empty(); }
    bool inside(float x, float y, float z) const;

    // Pushes the point out of every box it is in. Returns false if it is still inside a box after
    // that (a pocket enclosed by overlapping boxes): the caller then falls back to the particle's
    // previous, outside position.
    bool push_out(float& x, float& y, float& z, float& vx, float& vy, float& vz) const;

private:
    struct FloatBox {
        float lo[3];
        float hi[3];
    };
    std::vector<FloatBox> boxes_;
};

}  // namespace brume
