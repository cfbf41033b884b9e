#include "sim/noise.h"

#include "sim/rng.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace brume {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// sin^2(pi q) for |q| < 2^22 turns, branch-free so that the loop over particles vectorises with SSE2.
// q is reduced to f in [-1/2, 1/2] by the nearest integer (the 1.5 * 2^23 trick rounds without the
// rounding instruction SSE2 lacks; f = q - n is exact), and sin(pi f) = f P(f^2) with P the minimax
// fit of degree 4 (Lawson's algorithm; absolute error 3.3e-9, far below float rounding). Working in
// turns rather than radians saves the reduction's multiply by 2 pi and its split constant.
inline float sine_squared_turns(float q) {
    constexpr float kRound = 12582912.0f;  // 1.5 * 2^23
    const float f = q - ((q + kRound) - kRound);
    const float f2 = f * f;
    const float p = 3.14159258f + f2 * (-5.16770688f + f2 * (2.55003138f + f2 * (-0.598045168f + f2 * 0.0772201181f)));
    return f2 * (p * p);
}

// |v| clamped to `limit` (positive), as an integer operation on the magnitude bits (for non-negative
// floats the integer and float orders agree): it vectorises, where a float compare-and-select does not
// without -fno-trapping-math, and it maps NaN and infinity to +-limit.
inline float clamp_magnitude(float v, std::int32_t limit_bits) {
    const std::int32_t bits = std::bit_cast<std::int32_t>(v);
    const std::int32_t mag = bits & 0x7fffffff;
    return std::bit_cast<float>((mag < limit_bits ? mag : limit_bits) | (bits & std::int32_t(0x80000000u)));
}

// 1.0f where |x|, |y| and |z| are all below the limit, else 0.0f (NaN and infinity too), by integer
// operations on the magnitude bits, as clamp_magnitude.
inline float within_limit(float x, float y, float z, std::int32_t limit_bits) {
    const std::int32_t mx = std::bit_cast<std::int32_t>(x) & 0x7fffffff;
    const std::int32_t my = std::bit_cast<std::int32_t>(y) & 0x7fffffff;
    const std::int32_t mz = std::bit_cast<std::int32_t>(z) & 0x7fffffff;
    const std::int32_t inside = -(std::int32_t(mx < limit_bits) & std::int32_t(my < limit_bits) & std::int32_t(mz < limit_bits));
    return std::bit_cast<float>(inside & 0x3f800000);
}

// Particles per block of accumulate(): the clamped positions and the accumulators stay in L1.
constexpr std::size_t kBlock = 256;

}  // namespace

CurlNoise::CurlNoise(std::uint64_t key, const CurlNoiseParams& params) {
    const int m_per = kModesPerOctave;
    const double a = std::sqrt(2.0 / m_per);  // RMS speed 1 per octave: E|u|^2 = m a^2 / 2
    double octave_frequency = 1.0;
    double octave_gain = 1.0;
    for (int o = 0; o < params.octaves; ++o) {
        for (int m = 0; m < m_per; ++m) {
            const std::uint64_t mode_key = rng::hash(rng::kNoiseDomain, key, std::uint64_t(o), std::uint64_t(m));
            const auto u = [mode_key](int slot) { return rng::uniform(mode_key, std::uint64_t(slot)); };
            // Wave direction uniform on the sphere.
            const glm::dvec3 khat = rng::sphere_direction(u(0), u(1));
            // Potential direction uniform on the circle perpendicular to it.
            glm::dvec3 t, b;
            rng::orthonormal_basis(khat, t, b);
            const double pol = kTwoPi * u(2);
            const glm::dvec3 e = std::cos(pol) * t + std::sin(pol) * b;
            // Log-uniform over the octave band, so no single period dominates.
            const double cycles = 0.5 * std::exp2(u(3)) * octave_frequency;  // per noise unit
            Mode mode;
            mode.k = khat * (kTwoPi * cycles * params.frequency);
            mode.e = e;
            mode.amplitude = a * octave_gain * params.amplitude;
            mode.c = mode.amplitude * glm::cross(khat, e);
            mode.phase = kTwoPi * u(4);
            mode.omega = kTwoPi * cycles * (0.5 + 0.5 * u(5)) * (u(6) < 0.5 ? -1.0 : 1.0);
            modes_.push_back(mode);
        }
        octave_frequency *= params.lacunarity;
        octave_gain *= params.gain;
    }
    for (const Mode& mode : modes_) {
        const glm::dvec3 turns = mode.k / kTwoPi;
        kx_.push_back(float(turns.x));
        ky_.push_back(float(turns.y));
        kz_.push_back(float(turns.z));
        cx2_.push_back(float(-2.0 * mode.c.x));
        cy2_.push_back(float(-2.0 * mode.c.y));
        cz2_.push_back(float(-2.0 * mode.c.z));
    }
    for (std::size_t first = 0; first < modes_.size(); first += m_per) {
        glm::dvec3 c_sum{0.0};
        double k1_max = 0.0;  // largest |k|_1 in turns per unit
        bool silent = true;
        for (std::size_t m = first; m < first + m_per; ++m) {
            const glm::dvec3 turns = modes_[m].k / kTwoPi;
            k1_max = std::max(k1_max, std::abs(turns.x) + std::abs(turns.y) + std::abs(turns.z));
            c_sum += modes_[m].c;
            silent = silent && cx2_[m] == 0.0f && cy2_[m] == 0.0f && cz2_[m] == 0.0f;
        }
        // |q| <= |k|_1 * limit + 1/2 < 2^22 keeps sine_squared_turns exact in its reduction.
        const double limit = k1_max > 0.0 ? std::min(0x1.0p21 / k1_max, 1e30) : 1e30;
        octaves_.push_back({first, glm::vec3(c_sum), std::bit_cast<std::int32_t>(float(limit)), silent});
    }
}

void CurlNoise::phases(double tau, float* out) const {
    for (std::size_t m = 0; m < modes_.size(); ++m) {
        const double turns = (modes_[m].phase + modes_[m].omega * tau) / kTwoPi;
        out[m] = float(turns - std::nearbyint(turns));
    }
}

// cos(2 pi q) = 1 - 2 sin^2(pi q), so sum_m c_m cos(.) = sum_m c_m + sum_m (-2 c_m) sin^2(.): each
// octave's constant sum is added once and each mode costs one polynomial and three multiply-adds. Modes
// are the inner loop's outer loop so that the innermost is a plain vectorisable sweep over a block of
// particles; each octave's sum is weighted 1 where the particle lies within its limit, else 0.
void CurlNoise::accumulate(const float* x, const float* y, const float* z, std::size_t n, const float* phases,
                           float* ax, float* ay, float* az) const {
    alignas(64) float px[kBlock], py[kBlock], pz[kBlock], w[kBlock], ux[kBlock], uy[kBlock], uz[kBlock];
    alignas(64) float vx[kBlock], vy[kBlock], vz[kBlock];
    // The smallest limit of the octaves taken: a block whose positions all lie within it (every block, at
    // ordinary scales) needs no clamp and weighs every octave 1, the same sums bit for bit, so its
    // octaves read the positions as they are (the clamps and weights had cost 10% of the simulator's
    // instructions in bench sim).
    std::int32_t finest_limit = std::numeric_limits<std::int32_t>::max();
    for (const Octave& octave : octaves_)
        if (!octave.silent) finest_limit = std::min(finest_limit, octave.limit_bits);
    for (std::size_t i0 = 0; i0 < n; i0 += kBlock) {
        const std::size_t b = std::min(kBlock, n - i0);
        for (std::size_t i = 0; i < b; ++i) ux[i] = uy[i] = uz[i] = 0.0f;
        std::int32_t largest = 0;  // the largest magnitude's bits (NaN's exceed every limit)
        for (std::size_t i = 0; i < b; ++i)
            largest = std::max({largest, std::bit_cast<std::int32_t>(x[i0 + i]) & 0x7fffffff,
                                std::bit_cast<std::int32_t>(y[i0 + i]) & 0x7fffffff,
                                std::bit_cast<std::int32_t>(z[i0 + i]) & 0x7fffffff});
        const bool all_within = largest < finest_limit;
        for (const Octave& octave : octaves_) {
            if (octave.silent) continue;
            const float *qx = x + i0, *qy = y + i0, *qz = z + i0;
            if (!all_within) {
                // Positions past the octave's limit (hundreds of kilometres for the first octaves at
                // ordinary scales) are clamped, so every argument stays in the reduction's exact range,
                // and weighted 0.
                for (std::size_t i = 0; i < b; ++i) {
                    px[i] = clamp_magnitude(x[i0 + i], octave.limit_bits);
                    py[i] = clamp_magnitude(y[i0 + i], octave.limit_bits);
                    pz[i] = clamp_magnitude(z[i0 + i], octave.limit_bits);
                    w[i] = within_limit(x[i0 + i], y[i0 + i], z[i0 + i], octave.limit_bits);
                }
                qx = px;
                qy = py;
                qz = pz;
            }
            for (std::size_t i = 0; i < b; ++i) {
                vx[i] = octave.c_sum.x;
                vy[i] = octave.c_sum.y;
                vz[i] = octave.c_sum.z;
            }
            for (std::size_t m = octave.first; m < octave.first + kModesPerOctave; ++m) {
                const float kx = kx_[m], ky = ky_[m], kz = kz_[m], theta = phases[m];
                const float cx = cx2_[m], cy = cy2_[m], cz = cz2_[m];
                for (std::size_t i = 0; i < b; ++i) {
                    const float s2 = sine_squared_turns(kx * qx[i] + ky * qy[i] + kz * qz[i] + theta);
                    vx[i] += cx * s2;
                    vy[i] += cy * s2;
                    vz[i] += cz * s2;
                }
            }
            if (all_within) {
                for (std::size_t i = 0; i < b; ++i) {
                    ux[i] += vx[i];
                    uy[i] += vy[i];
                    uz[i] += vz[i];
                }
            } else {
                for (std::size_t i = 0; i < b; ++i) {
                    ux[i] += w[i] * vx[i];
                    uy[i] += w[i] * vy[i];
                    uz[i] += w[i] * vz[i];
                }
            }
        }
        for (std::size_t i = 0; i < b; ++i) {
            ax[i0 + i] += ux[i];
            ay[i0 + i] += uy[i];
            az[i0 + i] += uz[i];
        }
    }
}

glm::dvec3 CurlNoise::velocity(const glm::dvec3& x, double tau) const {
    glm::dvec3 u{0.0};
    for (const Mode& m : modes_) u += m.c * std::cos(glm::dot(m.k, x) + m.phase + m.omega * tau);
    return u;
}

glm::dvec3 CurlNoise::potential(const glm::dvec3& x, double tau) const {
    glm::dvec3 psi{0.0};
    for (const Mode& m : modes_)
        psi += (m.amplitude / glm::length(m.k)) * std::sin(glm::dot(m.k, x) + m.phase + m.omega * tau) * m.e;
    return psi;
}

}  // namespace brume
