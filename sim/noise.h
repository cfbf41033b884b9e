// Curl noise: a smooth, time-varying, divergence-free random vector field for turbulence.
//
// Design: the vector potential is a sum of randomly oriented sinusoids (random Fourier modes, the
// "kinematic simulation" model of turbulence),
//     psi(x, tau) = sum_m (a_m / |k_m|) sin(k_m . x + phi_m + w_m tau) e_m,      e_m perpendicular to k_m,
// and the field is its curl, written out analytically:
//     u(x, tau)   = sum_m a_m cos(k_m . x + phi_m + w_m tau) (khat_m x e_m).
// Each term is divergence-free exactly (its divergence is -a sin(.) k.(khat x e) = 0), so the sum is,
// at every point and time, with no lattice, no interpolation and no seams. Each mode costs one
// dot product, one polynomial cosine and three multiply-adds, with no table lookups, so the SoA loop
// vectorises fully (SSE2, 4 floats); a lattice noise needs 8 gathers per field per octave instead.
// The float loop's own divergence is float rounding: c_m is perpendicular to k_m to 1e-7.
// Quality: directions are uniform on the sphere, so the field is statistically isotropic and
// homogeneous; wave numbers are log-uniform over one octave band per octave, so there is no single
// period; and every mode travels at its own speed, so the field evolves rather than scrolls.
//
// Octave o has wave numbers in [0.5, 1) * lacunarity^o cycles per noise unit and amplitude gain^o;
// each octave alone has an RMS speed of 1 (a_m = sqrt(2 / modes)). `tau` is noise time: a mode of
// f cycles per unit changes phase at 2 pi f (0.5 to 1) radians per unit of tau.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace brume {

struct CurlNoiseParams {
    int octaves = 1;
    double lacunarity = 2.0;
    double gain = 0.5;
    double frequency = 1.0;  // world to noise coordinates: the field at x is the noise at x * frequency
    double amplitude = 1.0;  // multiplies the whole field
};

class CurlNoise {
public:
    // 16 modes per octave: fewer start to look like interfering waves; the cost is linear in the
    // count (about 0.8 ns per mode per particle on one core, SSE2).
    static constexpr int kModesPerOctave = 16;

    CurlNoise() = default;
    CurlNoise(std::uint64_t key, const CurlNoiseParams& params);

    std::size_t mode_count() const { return kx_.size(); }

    // Every mode's phase at noise time tau in turns, wrapped to [-1/2, 1/2] in double before rounding
    // to float, so the float loop stays accurate however long the run. Computed once per step.
    void phases(double tau, float* out) const;

    // ax[i] += u(x_i) for n particles; `phases` from phases(). Works through blocks of 256 particles,
    // so that every mode sweeps data in L1.
    void accumulate(const float* x, const float* y, const float* z, std::size_t n, const float* phases,
                    float* ax, float* ay, float* az) const;

    // The same field and its potential in double precision with std::cos, from the same modes: the
    // reference the tests check the float loop and the divergence against.
    glm::dvec3 velocity(const glm::dvec3& x, double tau) const;
    glm::dvec3 potential(const glm::dvec3& x, double tau) const;

private:
    // Per mode, in double (reference, phases) and in float (the hot loop).
    struct Mode {
        glm::dvec3 k{0.0};         // wave vector in world units (frequency applied)
        glm::dvec3 e{0.0};         // potential direction, perpendicular to k
        glm::dvec3 c{0.0};         // a * (khat x e): the velocity amplitude
        double amplitude = 0.0;    // a
        double phase = 0.0;        // phi
        double omega = 0.0;        // w, radians per unit of tau
    };
    std::vector<Mode> modes_;
    std::vector<float> kx_, ky_, kz_;       // float wave vectors in turns (cycles) per unit: k / 2 pi
    std::vector<float> cx2_, cy2_, cz2_;    // -2 c: cos = 1 - 2 sin^2(half), see accumulate()
    // Each octave's modes (kModesPerOctave from `first`), the sum of their c, and the distance from the
    // origin within which float positions resolve its waves (2^21 turns of its highest wave number):
    // beyond it the octave is left out for that particle, as its mean over space is 0. One limit for all
    // octaves, the finest's, clamped every particle past it for the coarse ones too: 16 octaves at
    // lacunarity 16 made the whole field one constant, and a clump drifted rigidly.
    struct Octave {
        std::size_t first = 0;
        glm::vec3 c_sum{0.0f};
        std::int32_t limit_bits = 0;
        bool silent = false;  // every c 0 (a gain of 0): skipped
    };
    std::vector<Octave> octaves_;
};

}  // namespace brume
