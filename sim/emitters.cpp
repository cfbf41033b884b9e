#include "sim/emitters.h"

#include "sim/density_sampler.h"
#include "sim/rng.h"
#include "sim/scene_file.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace brume {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Which draw of a particle's key each quantity uses: fixed slots, so adding a quantity later does not
// change the others.
enum Slot : std::uint64_t {
    kPos0, kPos1, kPos2,         // shape sample
    kConeCos, kConeAzimuth,      // direction in the cone
    kSpeed,
    kJitter0, kJitter1, kJitter2,
    kLifetime, kRadius, kExtinction,
    kAlbedoR, kAlbedoG, kAlbedoB,
    kPos3,                       // density shape: the voxel (kPos0..2 are its tent offsets)
};

double lerp(const Range& r, double u) { return r.min + (r.max - r.min) * u; }

// Unit vector, or `fallback` for a zero (or non-finite) input, so a degenerate preset cannot make NaNs.
glm::dvec3 unit_or(const glm::dvec3& v, const glm::dvec3& fallback) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? v / len : fallback;
}

// Uniform in the ball of the given radius: the radius's CDF is (r / R)^3.
glm::dvec3 ball_point(double radius, double u_r, double u_z, double u_azimuth) {
    return radius * std::cbrt(u_r) * rng::sphere_direction(u_z, u_azimuth);
}

glm::dvec3 sample_position(const EmitterDesc& e, std::uint64_t key) {
    const double u0 = rng::uniform(key, kPos0), u1 = rng::uniform(key, kPos1), u2 = rng::uniform(key, kPos2);
    switch (e.shape) {
    case EmitterShape::Point:
        return e.center;
    case EmitterShape::Sphere:
        return e.center + ball_point(e.radius, u0, u1, u2);
    case EmitterShape::Box:
        return e.center + e.half_extent * (2.0 * glm::dvec3{u0, u1, u2} - 1.0);
    case EmitterShape::Disc: {
        // Uniform in area: the radius's CDF is (r / R)^2.
        glm::dvec3 t, b;
        rng::orthonormal_basis(unit_or(e.normal, {0.0, 1.0, 0.0}), t, b);
        const double r = e.radius * std::sqrt(u0);
        const double phi = 2.0 * kPi * u1;
        return e.center + r * (std::cos(phi) * t + std::sin(phi) * b);
    }
    case EmitterShape::Density:
        require_density_loaded(e);
        return e.density->sample(rng::uniform(key, kPos3), u0, u1, u2);
    }
    return e.center;
}

// Uniform on the spherical cap of half-angle cone_deg around `direction`: cos(theta) is uniform on
// [cos(cone), 1] (the cap's area is linear in cos(theta)), the azimuth uniform.
glm::dvec3 sample_direction(const EmitterDesc& e, std::uint64_t key) {
    const glm::dvec3 axis = unit_or(e.direction, {0.0, 1.0, 0.0});
    const double cone = std::clamp(e.cone_deg, 0.0, 180.0) * (kPi / 180.0);
    const double cos_theta = 1.0 - rng::uniform(key, kConeCos) * (1.0 - std::cos(cone));
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const double phi = 2.0 * kPi * rng::uniform(key, kConeAzimuth);
    glm::dvec3 t, b;
    rng::orthonormal_basis(axis, t, b);
    return cos_theta * axis + sin_theta * (std::cos(phi) * t + std::sin(phi) * b);
}

}  // namespace

void require_density_loaded(const EmitterDesc& e) {
    if (e.shape == EmitterShape::Density && !e.density)
        throw std::logic_error("emitter " + toml_text::quoted(e.name) +
                               ": its density grid was not loaded (call load_emitter_densities)");
}

std::uint64_t continuous_count(const EmitterDesc& e, double t) {
    if (!(e.rate > 0.0)) return 0;
    const double end = std::min(t, e.stop);
    if (!(end > e.start)) return 0;
    const double x = e.rate * (end - e.start);
    const double n = std::floor(x * (1.0 + 1e-10));
    return n >= 0x1.0p63 ? std::uint64_t(1) << 63 : std::uint64_t(n);
}

double continuous_birth_time(const EmitterDesc& e, std::uint64_t n) {
    return e.start + double(n + 1) / e.rate;
}

Particle sample_particle(const EmitterDesc& e, std::uint64_t seed, std::uint32_t emitter_index,
                         std::uint64_t counter) {
    const std::uint64_t key = rng::hash(rng::kEmitterDomain, seed, emitter_index, counter);
    const auto u = [key](Slot s) { return rng::uniform(key, s); };
    Particle p;
    p.position = sample_position(e, key);
    const double speed = lerp(e.speed, u(kSpeed));
    p.velocity = speed * sample_direction(e, key) + ball_point(e.jitter, u(kJitter0), u(kJitter1), u(kJitter2));
    p.age = 0.0;
    p.lifetime = lerp(e.lifetime, u(kLifetime));
    p.radius = lerp(e.radius_range, u(kRadius));
    p.extinction = lerp(e.extinction, u(kExtinction));
    p.albedo = {e.albedo.min.x + (e.albedo.max.x - e.albedo.min.x) * u(kAlbedoR),
                e.albedo.min.y + (e.albedo.max.y - e.albedo.min.y) * u(kAlbedoG),
                e.albedo.min.z + (e.albedo.max.z - e.albedo.min.z) * u(kAlbedoB)};
    p.emitter = emitter_index;
    p.id = make_particle_id(emitter_index, counter);
    return p;
}

namespace {

// Keys (a, rgb), a ascending, linearly interpolated, held at the ends; 1 when there are none.
glm::dvec3 ramp_at(const std::vector<AgeCurves::AlbedoKey>& keys, double a) {
    if (keys.empty()) return glm::dvec3{1.0};
    if (a <= keys.front().age) return keys.front().multiplier;
    if (a >= keys.back().age) return keys.back().multiplier;
    // First key strictly after a; the one before it is at or before a, so the segment has length.
    const auto hi = std::upper_bound(keys.begin(), keys.end(), a,
                                     [](double v, const AgeCurves::AlbedoKey& k) { return v < k.age; });
    const auto lo = hi - 1;
    const double s = (a - lo->age) / (hi->age - lo->age);
    return lo->multiplier + (hi->multiplier - lo->multiplier) * s;
}

}  // namespace

AgeCurveFactors evaluate_age_curves(const AgeCurves& c, double a) {
    a = std::clamp(a, 0.0, 1.0);
    AgeCurveFactors f;
    f.radius = 1.0 + (c.radius_growth - 1.0) * a;
    // The two fades are ramps; where they overlap (fade_in + fade_out > 1) the lower one wins, so the
    // factor stays continuous, piecewise linear and never above 1.
    double fade = 1.0;
    if (c.fade_in > 0.0) fade = std::min(fade, a / c.fade_in);
    if (c.fade_out > 0.0) fade = std::min(fade, (1.0 - a) / c.fade_out);
    f.extinction = fade;
    f.albedo = ramp_at(c.albedo_ramp, a);
    f.emission = ramp_at(c.emission_ramp, a);
    return f;
}

}  // namespace brume
