// Emitters: emission counts and timing against floor(rate * t), sampling distributions against their
// closed forms, the particle budget and the age curves.
//
// Statistical tests use fixed seeds, so each is deterministic. Thresholds are the 0.1% critical values:
// sqrt(n) * D < 1.95 for Kolmogorov-Smirnov, and the chi-square quantile for the bins' degrees of
// freedom. A correct sampler passes with probability 99.9% for a random seed; the usual sampling
// mistakes (radius uniform instead of r^3 or r^2, angle uniform instead of cos(theta)) push the
// statistics into the tens with these sample sizes.
#include "sim/emitters.h"
#include "sim/simulator.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 20000;
constexpr double kKsCritical = 1.95;  // sqrt(n) * D at the 0.1% level

// sqrt(n) times the Kolmogorov-Smirnov distance of samples (supposed uniform on [0, 1]) from uniform.
double ks_uniform(std::vector<double> u) {
    std::sort(u.begin(), u.end());
    const double n = double(u.size());
    double d = 0.0;
    for (std::size_t i = 0; i < u.size(); ++i) {
        d = std::max(d, std::abs(double(i + 1) / n - u[i]));
        d = std::max(d, std::abs(u[i] - double(i) / n));
    }
    return std::sqrt(n) * d;
}

// Chi-square statistic of counts against equal expected counts, and its 0.1% critical value
// (Wilson-Hilferty approximation, accurate to a few percent for these degrees of freedom).
double chi_square(const std::vector<int>& counts) {
    double total = 0.0;
    for (int c : counts) total += c;
    const double expected = total / double(counts.size());
    double chi2 = 0.0;
    for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
    return chi2;
}
double chi_square_critical(int dof) {
    const double z = 3.090;  // the standard normal's 99.9% quantile
    const double k = dof;
    const double t = 1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k));
    return k * t * t * t;
}

double wrap_angle01(double angle) {
    double u = angle / (2.0 * kPi);
    return u - std::floor(u);
}

// A unit vector perpendicular to n, independent of the code under test.
dvec3 any_perpendicular(const dvec3& n) {
    const dvec3 other = std::abs(n.x) < 0.9 ? dvec3{1.0, 0.0, 0.0} : dvec3{0.0, 1.0, 0.0};
    return glm::normalize(glm::cross(n, other));
}

std::vector<Particle> samples(const EmitterDesc& e, std::uint64_t seed = 11, int n = kSamples) {
    std::vector<Particle> out;
    for (int i = 0; i < n; ++i) out.push_back(sample_particle(e, seed, 0, std::uint64_t(i)));
    return out;
}

// A preset with one emitter and nothing else: particles live long unless the test says otherwise.
Preset one_emitter(const EmitterDesc& e, double fps, int substeps) {
    Preset p;
    p.timeline.fps = fps;
    p.timeline.substeps = substeps;
    p.timeline.max_particles = 10'000'000;
    p.emitters.push_back(e);
    return p;
}

// One particle, born at time 0 and living `lifetime` seconds.
EmitterDesc lone_particle(double lifetime) {
    EmitterDesc e;
    e.bursts = {{0.0, 1}};
    e.lifetime = {lifetime, lifetime};
    return e;
}

EmitterDesc long_lived(double rate) {
    EmitterDesc e;
    e.rate = rate;
    e.lifetime = {1e6, 1e6};
    return e;
}

// ---------------------------------------------------------------------------------------------------
// Timing

TEST(EmissionCount, IsFloorRateTimesTimeAtEveryFrame) {
    // 30/s at 48 steps/s: t = k / 48 and 30 t = 5k / 8 exactly, so floor is an integer division.
    Simulator sim(one_emitter(long_lived(30.0), 24.0, 2));
    for (int f = 1; f <= 200; ++f) {
        sim.step_frame();
        const std::uint64_t k = std::uint64_t(2 * f);
        ASSERT_EQ(sim.emitted(0), 30 * k / 48) << "frame " << f;
        ASSERT_EQ(sim.size(), 30 * k / 48) << "frame " << f;
    }
}

TEST(EmissionCount, DecimalRateDoesNotDriftOrLoseRoundingBoundaries) {
    // 7.3/s at 90 steps/s: count = floor(73 k / 900). 7.3 is not exact in binary, and at k = 900 the
    // exact count 73 sits on the boundary that naive floating point rounds down to 72.
    Simulator sim(one_emitter(long_lived(7.3), 30.0, 3));
    for (int f = 1; f <= 1000; ++f) {
        sim.step_frame();
        const std::uint64_t k = std::uint64_t(3 * f);
        ASSERT_EQ(sim.emitted(0), 73 * k / 900) << "frame " << f;
    }
}

TEST(EmissionCount, RespectsStartAndStop) {
    EmitterDesc e = long_lived(10.0);
    e.start = 0.5;
    e.stop = 1.25;
    Simulator sim(one_emitter(e, 20.0, 1));
    for (int f = 1; f <= 60; ++f) {
        sim.step_frame();
        // Integer form of floor(10 * (clamp(t, 0.5, 1.25) - 0.5)) with t = f / 20.
        const int t20 = std::clamp(f, 10, 25);  // t in units of 1/20 s
        ASSERT_EQ(sim.emitted(0), std::uint64_t((t20 - 10) / 2)) << "frame " << f;
    }
    EXPECT_EQ(sim.emitted(0), 7u);
}

TEST(EmissionTiming, AgesAreTimeSinceBirthNotClumpedPerStep) {
    // 100/s with only 10 steps/s: ten births per step, each with its own age t - (n + 1) / rate.
    Simulator sim(one_emitter(long_lived(100.0), 10.0, 1));
    for (int f = 0; f < 5; ++f) sim.step_frame();
    const Particles& p = sim.particles();
    ASSERT_EQ(p.size(), 50u);
    std::set<float> ages;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::uint64_t n = p.id[i] & ((std::uint64_t(1) << kParticleIdCounterBits) - 1);
        const double expected = sim.time() - double(n + 1) / 100.0;
        EXPECT_NEAR(p.age[i], expected, 1e-5) << "particle " << n;
        ages.insert(p.age[i]);
    }
    EXPECT_GE(ages.size(), 45u);  // clumped emission would give 5 distinct ages
}

TEST(EmissionTiming, BurstsAtTheirTimes) {
    EmitterDesc e = long_lived(0.0);
    e.bursts = {{0.25, 3}, {0.0, 5}, {0.3, 2}};  // unsorted on purpose
    Simulator sim(one_emitter(e, 8.0, 1));        // steps end at k / 8: 0.25 is a boundary
    EXPECT_EQ(sim.size(), 5u);                    // births at time <= 0 are in the initial state
    for (std::size_t i = 0; i < sim.size(); ++i) EXPECT_EQ(sim.particles().age[i], 0.0f);
    sim.step_frame();  // t = 0.125
    EXPECT_EQ(sim.size(), 5u);
    sim.step_frame();  // t = 0.25: the burst at 0.25 is in, at age 0
    ASSERT_EQ(sim.size(), 8u);
    int newborn = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) newborn += sim.particles().age[i] == 0.0f;
    EXPECT_EQ(newborn, 3);
    sim.step_frame();  // t = 0.375: the burst at 0.3 has age 0.075
    ASSERT_EQ(sim.size(), 10u);
    int young = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) young += std::abs(sim.particles().age[i] - 0.075f) < 1e-6f;
    EXPECT_EQ(young, 2);
}

// ---------------------------------------------------------------------------------------------------
// Shapes

TEST(EmitterShapes, PointEmitsAtItsCentre) {
    EmitterDesc e;
    e.shape = EmitterShape::Point;
    e.center = {1.5, -2.0, 0.25};
    for (const Particle& p : samples(e, 3, 100)) EXPECT_EQ(p.position, e.center);
}

TEST(EmitterShapes, SphereIsUniformInTheVolume) {
    EmitterDesc e;
    e.shape = EmitterShape::Sphere;
    e.center = {1.0, 2.0, -3.0};
    e.radius = 2.5;
    std::vector<double> radial, polar, azimuth;
    std::vector<int> octants(8, 0);
    for (const Particle& p : samples(e)) {
        const dvec3 d = p.position - e.center;
        const double r = glm::length(d);
        ASSERT_LE(r, e.radius * (1.0 + 1e-12));
        radial.push_back(std::pow(r / e.radius, 3.0));  // the volume inside radius r: uniform
        polar.push_back(0.5 * (1.0 + d.z / r));          // cos(theta): uniform
        azimuth.push_back(wrap_angle01(std::atan2(d.y, d.x)));
        octants[(d.x > 0) + 2 * (d.y > 0) + 4 * (d.z > 0)]++;
    }
    EXPECT_LT(ks_uniform(radial), kKsCritical);
    EXPECT_LT(ks_uniform(polar), kKsCritical);
    EXPECT_LT(ks_uniform(azimuth), kKsCritical);
    EXPECT_LT(chi_square(octants), chi_square_critical(7));
}

TEST(EmitterShapes, BoxIsUniformInTheVolume) {
    EmitterDesc e;
    e.shape = EmitterShape::Box;
    e.center = {0.5, 1.0, -1.0};
    e.half_extent = {2.0, 0.5, 1.0};
    std::vector<double> u[3];
    std::vector<int> cells(64, 0);  // 4 x 4 x 4: also checks the axes are independent
    for (const Particle& p : samples(e)) {
        int cell = 0;
        for (int a = 0; a < 3; ++a) {
            const double t = (p.position[a] - e.center[a] + e.half_extent[a]) / (2.0 * e.half_extent[a]);
            ASSERT_GE(t, 0.0);
            ASSERT_LE(t, 1.0);
            u[a].push_back(t);
            cell = cell * 4 + std::min(3, int(t * 4.0));
        }
        cells[std::size_t(cell)]++;
    }
    for (int a = 0; a < 3; ++a) EXPECT_LT(ks_uniform(u[a]), kKsCritical) << "axis " << a;
    EXPECT_LT(chi_square(cells), chi_square_critical(63));
}

TEST(EmitterShapes, DiscIsUniformInTheDiscWithItsNormal) {
    EmitterDesc e;
    e.shape = EmitterShape::Disc;
    e.center = {0.0, 1.0, 0.0};
    e.radius = 1.5;
    e.normal = {1.0, 2.0, -0.5};  // not unit, not an axis
    const dvec3 n = glm::normalize(e.normal);
    const dvec3 t = any_perpendicular(n);
    const dvec3 b = glm::cross(n, t);
    std::vector<double> area, azimuth;
    std::vector<int> sectors(16, 0);
    for (const Particle& p : samples(e)) {
        const dvec3 d = p.position - e.center;
        ASSERT_NEAR(glm::dot(d, n), 0.0, 1e-12);
        const double r = glm::length(d);
        ASSERT_LE(r, e.radius * (1.0 + 1e-12));
        area.push_back((r / e.radius) * (r / e.radius));  // area inside radius r: uniform
        const double phi = wrap_angle01(std::atan2(glm::dot(d, b), glm::dot(d, t)));
        azimuth.push_back(phi);
        sectors[std::min(15, int(phi * 16.0))]++;
    }
    EXPECT_LT(ks_uniform(area), kKsCritical);
    EXPECT_LT(ks_uniform(azimuth), kKsCritical);
    EXPECT_LT(chi_square(sectors), chi_square_critical(15));
}

// ---------------------------------------------------------------------------------------------------
// Velocity

TEST(EmitterVelocity, ConeDirectionsAreUniformOnTheCap) {
    EmitterDesc e;
    e.direction = {1.0, 2.0, 0.5};
    e.cone_deg = 35.0;
    e.speed = {1.0, 1.0};
    const dvec3 axis = glm::normalize(e.direction);
    const double cos_cone = std::cos(e.cone_deg * kPi / 180.0);
    const dvec3 t = any_perpendicular(axis);
    const dvec3 b = glm::cross(axis, t);
    std::vector<double> cap, azimuth;
    double sum_cos = 0.0;
    for (const Particle& p : samples(e)) {
        ASSERT_NEAR(glm::length(p.velocity), 1.0, 1e-12);
        const double c = glm::dot(p.velocity, axis);
        ASSERT_GE(c, cos_cone - 1e-12);
        cap.push_back((1.0 - c) / (1.0 - cos_cone));  // the cap's area above theta: uniform
        azimuth.push_back(wrap_angle01(std::atan2(glm::dot(p.velocity, b), glm::dot(p.velocity, t))));
        sum_cos += c;
    }
    EXPECT_LT(ks_uniform(cap), kKsCritical);
    EXPECT_LT(ks_uniform(azimuth), kKsCritical);
    // Mean of cos(theta) over the cap: (1 + cos(cone)) / 2; cos(theta) is uniform, so its standard
    // error is (1 - cos(cone)) / sqrt(12 n). 4 standard errors.
    const double mean = sum_cos / kSamples;
    EXPECT_NEAR(mean, 0.5 * (1.0 + cos_cone), 4.0 * (1.0 - cos_cone) / std::sqrt(12.0 * kSamples));
}

TEST(EmitterVelocity, ZeroConeIsTheDirectionAndFullConeTheSphere) {
    EmitterDesc e;
    e.direction = {0.0, 0.0, -3.0};
    e.speed = {2.0, 2.0};
    for (const Particle& p : samples(e, 5, 200)) {
        EXPECT_NEAR(p.velocity.x, 0.0, 1e-12);
        EXPECT_NEAR(p.velocity.y, 0.0, 1e-12);
        EXPECT_NEAR(p.velocity.z, -2.0, 1e-12);
    }
    e.cone_deg = 180.0;
    std::vector<double> z;
    for (const Particle& p : samples(e)) z.push_back(0.5 * (1.0 + p.velocity.z / 2.0));
    EXPECT_LT(ks_uniform(z), kKsCritical);
}

TEST(EmitterVelocity, SpeedRangeAndJitterBall) {
    EmitterDesc e;
    e.speed = {2.0, 3.0};
    std::vector<double> speed;
    for (const Particle& p : samples(e)) speed.push_back(glm::length(p.velocity) - 2.0);
    EXPECT_LT(ks_uniform(speed), kKsCritical);

    // Speed 0: the velocity is the jitter alone, uniform in a ball of radius 0.5.
    e.speed = {0.0, 0.0};
    e.jitter = 0.5;
    std::vector<double> volume, polar;
    for (const Particle& p : samples(e)) {
        const double r = glm::length(p.velocity);
        ASSERT_LE(r, 0.5 * (1.0 + 1e-12));
        volume.push_back(std::pow(r / 0.5, 3.0));
        polar.push_back(0.5 * (1.0 + p.velocity.z / r));
    }
    EXPECT_LT(ks_uniform(volume), kKsCritical);
    EXPECT_LT(ks_uniform(polar), kKsCritical);
}

// ---------------------------------------------------------------------------------------------------
// Properties and identity

TEST(EmitterProperties, RangesAreUniformAndIdsUnique) {
    EmitterDesc e;
    e.lifetime = {1.0, 3.0};
    e.radius_range = {0.1, 0.4};
    e.extinction = {2.0, 5.0};
    e.albedo.min = {0.2, 0.4, 0.6};
    e.albedo.max = {0.3, 0.8, 0.7};
    std::vector<double> life, radius, ext, alb[3];
    std::set<std::uint64_t> ids;
    int i = 0;
    for (const Particle& p : samples(e)) {
        life.push_back((p.lifetime - 1.0) / 2.0);
        radius.push_back((p.radius - 0.1) / 0.3);
        ext.push_back((p.extinction - 2.0) / 3.0);
        for (int c = 0; c < 3; ++c)
            alb[c].push_back((p.albedo[c] - e.albedo.min[c]) / (e.albedo.max[c] - e.albedo.min[c]));
        EXPECT_EQ(p.id, make_particle_id(0, std::uint64_t(i++)));
        ids.insert(p.id);
    }
    EXPECT_LT(ks_uniform(life), kKsCritical);
    EXPECT_LT(ks_uniform(radius), kKsCritical);
    EXPECT_LT(ks_uniform(ext), kKsCritical);
    for (int c = 0; c < 3; ++c) EXPECT_LT(ks_uniform(alb[c]), kKsCritical) << "channel " << c;
    EXPECT_EQ(ids.size(), std::size_t(kSamples));
    // Draws must be independent of each other: lifetime and radius share no bits.
    double cov = 0.0;
    for (int k = 0; k < kSamples; ++k) cov += (life[std::size_t(k)] - 0.5) * (radius[std::size_t(k)] - 0.5);
    EXPECT_LT(std::abs(cov / kSamples), 4.0 * (1.0 / 12.0) / std::sqrt(double(kSamples)));
}

TEST(EmitterProperties, ParticleIsAFunctionOfSeedEmitterAndCounter) {
    EmitterDesc e;
    e.shape = EmitterShape::Sphere;
    e.radius = 1.0;
    e.cone_deg = 40.0;
    const Particle a = sample_particle(e, 9, 2, 17);
    const Particle b = sample_particle(e, 9, 2, 17);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.id, make_particle_id(2, 17));
    EXPECT_EQ(a.emitter, 2u);
    EXPECT_NE(a.position, sample_particle(e, 10, 2, 17).position);  // seed
    EXPECT_NE(a.position, sample_particle(e, 9, 3, 17).position);   // emitter
    EXPECT_NE(a.position, sample_particle(e, 9, 2, 18).position);   // counter
    EXPECT_NE(make_particle_id(2, 17), make_particle_id(3, 17));
}

// ---------------------------------------------------------------------------------------------------
// Budget

TEST(ParticleBudget, CapsTheLiveCountAndSkipsTheLatestBirths) {
    EmitterDesc e;
    e.rate = 2000.0;  // 200 births per step
    e.lifetime = {0.45, 0.45};
    Preset preset = one_emitter(e, 10.0, 1);
    preset.timeline.max_particles = 100;
    Simulator sim(preset);
    sim.step_frame();
    ASSERT_EQ(sim.size(), 100u);
    // The documented rule: births in order, the first ones fill the budget, the rest are skipped.
    std::set<std::uint64_t> ids(sim.particles().id.begin(), sim.particles().id.end());
    for (std::uint64_t n = 0; n < 100; ++n) EXPECT_TRUE(ids.count(make_particle_id(0, n))) << n;
    EXPECT_EQ(sim.emitted(0), 200u);
    EXPECT_EQ(sim.skipped(), 100u);
    bool refilled = false;
    for (int f = 0; f < 30; ++f) {
        const std::uint64_t skipped_before = sim.skipped();
        sim.step_frame();
        ASSERT_LE(sim.size(), 100u) << "frame " << f;
        // Once the first generation dies (age >= 0.45), the same step's births take its place.
        if (sim.skipped() - skipped_before < 200) refilled = true;
    }
    EXPECT_TRUE(refilled);
    EXPECT_EQ(sim.size(), 100u);
}

// ---------------------------------------------------------------------------------------------------
// Age curves

TEST(AgeCurves, ClosedFormsAtKnownAges) {
    AgeCurves c;
    c.radius_growth = 3.0;
    c.fade_in = 0.2;
    c.fade_out = 0.25;
    c.albedo_ramp = {{0.2, {1.0, 1.0, 1.0}}, {0.6, {0.5, 0.7, 0.9}}, {0.8, {0.1, 0.2, 0.3}}};

    const AgeCurveFactors at0 = evaluate_age_curves(c, 0.0);
    EXPECT_DOUBLE_EQ(at0.radius, 1.0);
    EXPECT_DOUBLE_EQ(at0.extinction, 0.0);
    EXPECT_EQ(at0.albedo, dvec3(1.0, 1.0, 1.0));  // held before the first key

    const AgeCurveFactors a01 = evaluate_age_curves(c, 0.1);
    EXPECT_DOUBLE_EQ(a01.radius, 1.2);
    EXPECT_DOUBLE_EQ(a01.extinction, 0.5);

    const AgeCurveFactors a05 = evaluate_age_curves(c, 0.5);
    EXPECT_DOUBLE_EQ(a05.radius, 2.0);
    EXPECT_DOUBLE_EQ(a05.extinction, 1.0);
    EXPECT_NEAR(a05.albedo.x, 1.0 + (0.5 - 1.0) * 0.75, 1e-15);
    EXPECT_NEAR(a05.albedo.y, 1.0 + (0.7 - 1.0) * 0.75, 1e-15);
    EXPECT_NEAR(a05.albedo.z, 1.0 + (0.9 - 1.0) * 0.75, 1e-15);

    const AgeCurveFactors a09 = evaluate_age_curves(c, 0.9);
    EXPECT_DOUBLE_EQ(a09.radius, 2.8);
    EXPECT_NEAR(a09.extinction, 0.4, 1e-15);
    EXPECT_EQ(a09.albedo, dvec3(0.1, 0.2, 0.3));  // held after the last key

    const AgeCurveFactors a1 = evaluate_age_curves(c, 1.0);
    EXPECT_DOUBLE_EQ(a1.radius, 3.0);
    EXPECT_DOUBLE_EQ(a1.extinction, 0.0);

    // Defaults: no change at any age.
    const AgeCurveFactors none = evaluate_age_curves(AgeCurves{}, 0.37);
    EXPECT_EQ(none.radius, 1.0);
    EXPECT_EQ(none.extinction, 1.0);
    EXPECT_EQ(none.albedo, dvec3(1.0));
}

TEST(AgeCurves, AppliedToSpheresAtTheParticlesAges) {
    EmitterDesc e;
    e.bursts = {{0.0, 4}};
    e.lifetime = {2.0, 2.0};
    e.radius_range = {0.2, 0.2};
    e.extinction = {3.0, 3.0};
    e.albedo.min = e.albedo.max = {0.8, 0.6, 0.4};
    e.curves.radius_growth = 2.0;
    e.curves.fade_out = 0.5;
    e.curves.albedo_ramp = {{0.0, {1.0, 1.0, 1.0}}, {1.0, {0.5, 0.5, 0.5}}};
    Simulator sim(one_emitter(e, 10.0, 1));
    sim.advance_to_frame(15);  // age 1.5, a = 0.75
    std::vector<Sphere> spheres;
    sim.append_spheres(spheres);
    ASSERT_EQ(spheres.size(), 4u);
    for (const Sphere& s : spheres) {
        EXPECT_NEAR(s.radius, 0.2 * 1.75, 1e-6);
        EXPECT_NEAR(s.extinction, 3.0 * 0.5, 1e-5);
        EXPECT_NEAR(s.albedo.x, 0.8 * 0.625, 1e-6);
        EXPECT_NEAR(s.albedo.z, 0.4 * 0.625, 1e-6);
    }
}

// A particle dies when its age reaches its lifetime, however many steps that takes: ages summed step by
// step in float lost 1.7 s of a 100 s life at 240 fps and 64 substeps (it died at frame 23,602 of the
// 24,000), and stopped growing at 2,048 s, so that a 3,000 s life never ended.
TEST(AgeCurves, ALongLifeEndsOnTimeAtManySubsteps) {
    Simulator sim(one_emitter(lone_particle(100.0), 240.0, 64));
    sim.advance_to_frame(23'990);  // t = 99.96 s
    EXPECT_EQ(sim.size(), 1u);
    sim.advance_to_frame(24'010);  // t = 100.04 s
    EXPECT_EQ(sim.size(), 0u);
}

// Moves far below a float step still add up: a particle 1,000 units out at 0.5 units a second is 2 units
// further after 4 s at any substep count. With float positions alone each 3.3e-5 move of 64 substeps at
// 240 fps rounded to a whole float step there (6.1e-5), and the particle went 87% too fast; 100,000 units
// out it did not move at all.
TEST(Simulator, SlowMotionFarFromTheOriginAddsUpAtAnySubstepCount) {
    for (const double far : {1000.0, 100000.0}) {
        for (const int substeps : {1, 64}) {
            EmitterDesc e = lone_particle(100.0);
            e.center = {far, 1.0, 0.0};
            e.direction = {1.0, 0.0, 0.0};
            e.speed = {0.5, 0.5};
            Simulator sim(one_emitter(e, 240.0, substeps));
            sim.advance_to_frame(960);  // 4 s
            ASSERT_EQ(sim.size(), 1u);
            const dvec3 p = sim.particles().at(0).position;
            EXPECT_NEAR(p.x, far + 2.0, 1e-4 * (1.0 + far / 1000.0)) << far << " units out, " << substeps << " substeps";
        }
    }
}

TEST(AgeCurves, SpheresWithZeroRadiusOrExtinctionAreSkipped) {
    EmitterDesc faded;  // fade-in: extinction 0 at age 0
    faded.bursts = {{0.0, 3}};
    faded.curves.fade_in = 0.5;
    EmitterDesc clear;  // extinction 0 throughout
    clear.bursts = {{0.0, 2}};
    clear.extinction = {0.0, 0.0};
    EmitterDesc tiny;  // radius 0
    tiny.bursts = {{0.0, 2}};
    tiny.radius_range = {0.0, 0.0};
    EmitterDesc solid;
    solid.bursts = {{0.0, 5}};
    Preset preset = one_emitter(faded, 10.0, 1);
    preset.emitters.push_back(clear);
    preset.emitters.push_back(tiny);
    preset.emitters.push_back(solid);
    Simulator sim(preset);
    ASSERT_EQ(sim.size(), 12u);
    std::vector<Sphere> spheres(1);  // appends after what is there
    sim.append_spheres(spheres);
    EXPECT_EQ(spheres.size(), 1u + 5u);
    sim.step_frame();  // the faded ones now have extinction > 0
    spheres.clear();
    sim.append_spheres(spheres);
    EXPECT_EQ(spheres.size(), 8u);
}

}  // namespace
}  // namespace brume
