#include "sim/forces.h"

#include "sim/rng.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {

LinearStep make_linear_step(double k, double dt) {
    const double x = k * dt;
    double phi1, phi2;
    if (std::abs(x) < 1e-3) {
        // Taylor series of (1 - e^-x) / x and (x - 1 + e^-x) / x^2; the next terms are below 1e-13.
        phi1 = dt * (1.0 - x * (1.0 / 2.0 - x * (1.0 / 6.0 - x * (1.0 / 24.0))));
        phi2 = dt * dt * (1.0 / 2.0 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x * (1.0 / 120.0))));
    } else {
        phi1 = -std::expm1(-x) / k;
        phi2 = (dt - phi1) / k;
    }
    return {float(std::exp(-x)), float(phi1), float(phi2)};
}

ForceField::ForceField(const std::vector<ForceDesc>& forces, std::uint64_t seed) {
    for (std::size_t i = 0; i < forces.size(); ++i) {
        const ForceDesc& f = forces[i];
        switch (f.kind) {
        case ForceKind::Gravity:
            constant_ += f.vector;
            break;
        case ForceKind::Buoyancy:
            constant_ += glm::dvec3{0.0, f.strength, 0.0};
            break;
        case ForceKind::Wind:
            // strength * (vector - v): a constant part and a share of the linear rate.
            constant_ += f.strength * f.vector;
            k_ += f.strength;
            break;
        case ForceKind::Drag:
            k_ += f.strength;
            break;
        case ForceKind::Turbulence: {
            CurlNoiseParams p;
            p.octaves = f.octaves;
            p.lacunarity = f.lacunarity;
            p.gain = f.gain;
            p.frequency = f.scale;
            p.amplitude = f.strength;
            turbulence_.push_back({CurlNoise(rng::hash(seed, i), p), f.speed});
            phase_count_ += turbulence_.back().noise.mode_count();
            break;
        }
        case ForceKind::Vortex: {
            const double len = glm::length(f.axis);
            Vortex v;
            v.center = f.center;
            v.axis = len > 0.0 && std::isfinite(len) ? f.axis / len : glm::dvec3{0.0, 1.0, 0.0};
            v.strength = f.strength;
            // A floor far below any real radius keeps a particle exactly on the axis at a = 0 (not 0/0)
            // should a preset give radius 0.
            v.radius2 = std::max(f.radius * f.radius, 1e-30);
            vortices_.push_back(v);
            break;
        }
        }
    }
}

void ForceField::phases(double t, float* out) const {
    for (const Turbulence& tb : turbulence_) {
        tb.noise.phases(t * tb.speed, out);
        out += tb.noise.mode_count();
    }
}

void ForceField::accelerations(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                               std::size_t n, const float* __restrict phases, float* __restrict ax,
                               float* __restrict ay, float* __restrict az) const {
    const glm::vec3 c(constant_);
    for (std::size_t i = 0; i < n; ++i) {
        ax[i] = c.x;
        ay[i] = c.y;
        az[i] = c.z;
    }
    for (const Turbulence& tb : turbulence_) {
        tb.noise.accumulate(x, y, z, n, phases, ax, ay, az);
        phases += tb.noise.mode_count();
    }
    for (const Vortex& vd : vortices_) {
        const glm::vec3 o(vd.center), w(vd.axis);
        const float s = float(vd.strength), r2 = float(vd.radius2);
        for (std::size_t i = 0; i < n; ++i) {
            // r: offset from the axis line, perpendicular to it; a = s (w x r) / (|r|^2 + R^2).
            const float dx = x[i] - o.x, dy = y[i] - o.y, dz = z[i] - o.z;
            const float along = dx * w.x + dy * w.y + dz * w.z;
            const float rx = dx - along * w.x, ry = dy - along * w.y, rz = dz - along * w.z;
            const float f = s / (rx * rx + ry * ry + rz * rz + r2);
            ax[i] += f * (w.y * rz - w.z * ry);
            ay[i] += f * (w.z * rx - w.x * rz);
            az[i] += f * (w.x * ry - w.y * rx);
        }
    }
}

glm::dvec3 ForceField::acceleration(const glm::dvec3& x, const glm::dvec3& v, double t) const {
    glm::dvec3 a = constant_ - k_ * v;
    for (const Turbulence& tb : turbulence_) a += tb.noise.velocity(x, t * tb.speed);
    for (const Vortex& vd : vortices_) {
        const glm::dvec3 d = x - vd.center;
        const glm::dvec3 r = d - glm::dot(d, vd.axis) * vd.axis;
        a += vd.strength * glm::cross(vd.axis, r) / (glm::dot(r, r) + vd.radius2);
    }
    return a;
}

namespace {

// p + lo += d (TwoSum: the rounded sum and its exact rounding, kept in lo).
inline void move(float& p, float& lo, float d) {
    const float step = d + lo;
    const float s = p + step;
    const float step_rounded = s - p;
    lo = (p - (s - step_rounded)) + (step - step_rounded);
    p = s;
}

}  // namespace

void integrate(const LinearStep& step, const float* __restrict ax, const float* __restrict ay,
               const float* __restrict az, std::size_t n, float* __restrict x, float* __restrict y,
               float* __restrict z, float* __restrict x_lo, float* __restrict y_lo, float* __restrict z_lo,
               float* __restrict vx, float* __restrict vy, float* __restrict vz) {
    const float e = step.decay, p1 = step.phi1, p2 = step.phi2;
    for (std::size_t i = 0; i < n; ++i) {
        const float ux = vx[i], uy = vy[i], uz = vz[i];
        move(x[i], x_lo[i], ux * p1 + ax[i] * p2);
        move(y[i], y_lo[i], uy * p1 + ay[i] * p2);
        move(z[i], z_lo[i], uz * p1 + az[i] * p2);
        vx[i] = ux * e + ax[i] * p1;
        vy[i] = uy * e + ay[i] * p1;
        vz[i] = uz * e + az[i] * p1;
    }
}

namespace {

// The float nearest to v on the given side, so that comparisons against it agree with the double.
float round_down(double v) {
    float f = float(v);
    if (double(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
float round_up(double v) {
    float f = float(v);
    if (double(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

}  // namespace

BoxObstacles::BoxObstacles(const std::vector<Box>& boxes) {
    for (const Box& b : boxes) {
        // lo <= min and p > min <=> p > lo for every float p (likewise hi >= max).
        FloatBox f;
        for (int a = 0; a < 3; ++a) {
            f.lo[a] = round_down(b.min[a]);
            f.hi[a] = round_up(b.max[a]);
        }
        boxes_.push_back(f);
    }
}

bool BoxObstacles::inside(float x, float y, float z) const {
    for (const FloatBox& b : boxes_) {
        if (x > b.lo[0] && x < b.hi[0] && y > b.lo[1] && y < b.hi[1] && z > b.lo[2] && z < b.hi[2]) return true;
    }
    return false;
}

bool BoxObstacles::push_out(float& x, float& y, float& z, float& vx, float& vy, float& vz) const {
    float* p[3] = {&x, &y, &z};
    float* v[3] = {&vx, &vy, &vz};
    // Each pass leaves every box the point is in. Of a box's six faces the nearest one whose exit point
    // is outside every other box is taken, so overlapping boxes are left through the union's surface
    // rather than bounced between; if every exit lands in another box, the nearest is taken and the
    // next pass moves on from there. One pass per box bounds the walk.
    for (std::size_t pass = 0; pass <= boxes_.size(); ++pass) {
        bool moved = false;
        for (const FloatBox& b : boxes_) {
            if (!(x > b.lo[0] && x < b.hi[0] && y > b.lo[1] && y < b.hi[1] && z > b.lo[2] && z < b.hi[2]))
                continue;
            // Faces in the order x-min, x-max, y-min, ...: ties go to the earlier one.
            float depth[6];
            for (int a = 0; a < 3; ++a) {
                depth[2 * a] = *p[a] - b.lo[a];
                depth[2 * a + 1] = b.hi[a] - *p[a];
            }
            int chosen = -1, nearest = 0;
            bool taken[6] = {};
            for (int rank = 0; rank < 6 && chosen < 0; ++rank) {
                int f = -1;
                for (int c = 0; c < 6; ++c)
                    if (!taken[c] && (f < 0 || depth[c] < depth[f])) f = c;
                taken[f] = true;
                if (rank == 0) nearest = f;
                float q[3] = {x, y, z};
                q[f / 2] = f % 2 ? b.hi[f / 2] : b.lo[f / 2];
                if (!inside(q[0], q[1], q[2])) chosen = f;
            }
            if (chosen < 0) chosen = nearest;
            const int a = chosen / 2;
            if (chosen % 2) {
                *p[a] = b.hi[a];
                if (*v[a] < 0.0f) *v[a] = 0.0f;  // remove the velocity into the face (normal +axis)
            } else {
                *p[a] = b.lo[a];
                if (*v[a] > 0.0f) *v[a] = 0.0f;
            }
            moved = true;
        }
        if (!moved) return true;
    }
    return !inside(x, y, z);
}

}  // namespace brume
