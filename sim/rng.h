// Counter-based randomness for the simulator, and the sampling helpers emitters and noise share.
// Every random number is a pure function of (seed, what it is for, which particle or mode, which
// draw). Nothing is carried from one draw to the next, so a particle's values do not depend on how
// many particles came before it, on the step size, on the particle budget or on evaluation order,
// and two runs are bit-identical.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace brume::rng {

// splitmix64 (Steele, Lea & Flood 2014; Vigna's finaliser constants): add the golden-ratio gamma,
// then a bijective avalanche. Consecutive inputs give statistically independent outputs, which is
// exactly the property a counter-based generator needs.
constexpr std::uint64_t mix64(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Hash of four words, chained through mix64 so that every word changes every output bit.
constexpr std::uint64_t hash(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0, std::uint64_t d = 0) {
    return mix64(mix64(mix64(mix64(a) ^ b) ^ c) ^ d);
}

// The top 53 bits as a double in [0, 1): every value is an exact multiple of 2^-53.
constexpr double to_unit(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

// Draw number `slot` of a key made by hash(): uniform in [0, 1).
constexpr double uniform(std::uint64_t key, std::uint64_t slot) { return to_unit(mix64(key ^ mix64(slot))); }

// Domain tags keep the emitters' and the noise's keys apart even when their other words coincide.
inline constexpr std::uint64_t kEmitterDomain = 0x656d6974746572ull;  // "emitter"
inline constexpr std::uint64_t kNoiseDomain = 0x6e6f697365ull;        // "noise"

// Uniform on the unit sphere from two uniforms: z uniform in [-1, 1] (Archimedes), azimuth uniform.
inline glm::dvec3 sphere_direction(double u_z, double u_azimuth) {
    const double z = 1.0 - 2.0 * u_z;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 6.283185307179586476925286766559 * u_azimuth;
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// Two unit vectors completing the unit vector n to an orthonormal basis, without the near-singular
// cross product of the usual construction (Duff et al. 2017, "Building an orthonormal basis, revisited").
inline void orthonormal_basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

}  // namespace brume::rng
