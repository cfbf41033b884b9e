// The simulator as a whole: determinism (bit-identical replays, random access to frames, seeds),
// the clock and preroll, lifetime removal and the benchmark entry point.
#include "sim/emitters.h"
#include "sim/simulator.h"

#include "test_scenes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

using testing::force;

// Everything at once: two emitters (continuous and bursts), every force kind, boxes, a budget that
// binds, deaths, so that any hidden nondeterminism has somewhere to show.
Preset plume(std::uint64_t seed = 3) {
    Preset p;
    p.timeline.fps = 24.0;
    p.timeline.substeps = 2;
    p.timeline.seed = seed;
    p.timeline.max_particles = 1000;
    p.scene.boxes = {Box{{-5.0, -1.0, -5.0}, {5.0, 0.0, 5.0}, dvec3{0.2}},
                     Box{{1.0, 0.0, -0.5}, {2.0, 1.5, 0.5}, dvec3{0.2}}};
    EmitterDesc chimney;
    chimney.shape = EmitterShape::Disc;
    chimney.center = {0.0, 0.2, 0.0};
    chimney.radius = 0.3;
    chimney.rate = 400.0;
    chimney.speed = {0.5, 1.5};
    chimney.cone_deg = 25.0;
    chimney.jitter = 0.2;
    chimney.lifetime = {1.5, 3.0};
    chimney.radius_range = {0.05, 0.1};
    chimney.curves.radius_growth = 3.0;
    chimney.curves.fade_in = 0.1;
    chimney.curves.fade_out = 0.4;
    EmitterDesc puff;
    puff.shape = EmitterShape::Sphere;
    puff.center = {-1.0, 1.0, 0.0};
    puff.radius = 0.5;
    puff.bursts = {{0.0, 200}, {0.5, 300}, {1.2, 300}};
    puff.direction = {1.0, 0.0, 0.0};
    puff.cone_deg = 90.0;
    puff.lifetime = {0.5, 2.0};
    p.emitters = {chimney, puff};
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.0, -9.81, 0.0};
    ForceDesc buoyancy = force(ForceKind::Buoyancy);
    buoyancy.strength = 10.5;
    ForceDesc wind = force(ForceKind::Wind);
    wind.vector = {0.8, 0.0, 0.3};
    wind.strength = 0.5;
    ForceDesc drag = force(ForceKind::Drag);
    drag.strength = 0.2;
    ForceDesc turbulence = force(ForceKind::Turbulence);
    turbulence.strength = 2.0;
    turbulence.scale = 0.8;
    turbulence.speed = 0.6;
    turbulence.octaves = 2;
    ForceDesc vortex = force(ForceKind::Vortex);
    vortex.strength = 1.0;
    vortex.radius = 0.5;
    p.forces = {gravity, buoyancy, wind, drag, turbulence, vortex};
    return p;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool bit_identical(const Particles& a, const Particles& b) {
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z) && same_bits(a.vx, b.vx) &&
           same_bits(a.vy, b.vy) && same_bits(a.vz, b.vz) && same_bits(a.age, b.age) &&
           same_bits(a.lifetime, b.lifetime) && same_bits(a.radius, b.radius) &&
           same_bits(a.extinction, b.extinction) && same_bits(a.albedo_r, b.albedo_r) &&
           same_bits(a.albedo_g, b.albedo_g) && same_bits(a.albedo_b, b.albedo_b) &&
           same_bits(a.emitter, b.emitter) && same_bits(a.id, b.id);
}

TEST(Simulator, TwoRunsAreBitIdentical) {
    Simulator a(plume()), b(plume());
    bool budget_hit = false;
    for (int f = 0; f < 60; ++f) {
        a.step_frame();
        b.step_frame();
        ASSERT_TRUE(bit_identical(a.particles(), b.particles())) << "frame " << f;
        budget_hit |= a.skipped() > 0;
    }
    EXPECT_GT(a.size(), 100u);
    EXPECT_TRUE(budget_hit);
    std::vector<Sphere> sa, sb;
    a.append_spheres(sa);
    b.append_spheres(sb);
    ASSERT_EQ(sa.size(), sb.size());
    for (std::size_t i = 0; i < sa.size(); ++i) {
        ASSERT_EQ(sa[i].center, sb[i].center);
        ASSERT_EQ(sa[i].radius, sb[i].radius);
        ASSERT_EQ(sa[i].extinction, sb[i].extinction);
        ASSERT_EQ(sa[i].albedo, sb[i].albedo);
    }
}

TEST(Simulator, AdvanceToFrameEqualsSteppingAndReplays) {
    Simulator stepped(plume()), jumped(plume());
    for (int f = 0; f < 20; ++f) stepped.step_frame();
    jumped.advance_to_frame(20);
    EXPECT_EQ(jumped.frame(), 20);
    EXPECT_TRUE(bit_identical(stepped.particles(), jumped.particles()));

    // Going back replays from the start.
    Simulator fresh(plume());
    for (int f = 0; f < 7; ++f) fresh.step_frame();
    jumped.advance_to_frame(7);
    EXPECT_EQ(jumped.frame(), 7);
    EXPECT_TRUE(bit_identical(fresh.particles(), jumped.particles()));
    EXPECT_EQ(jumped.skipped(), fresh.skipped());
    jumped.advance_to_frame(7);  // no-op
    EXPECT_TRUE(bit_identical(fresh.particles(), jumped.particles()));
    jumped.advance_to_frame(0);
    EXPECT_TRUE(bit_identical(Simulator(plume()).particles(), jumped.particles()));
    EXPECT_THROW(jumped.advance_to_frame(-1), std::invalid_argument);
}

TEST(Simulator, DifferentSeedsDiffer) {
    Simulator a(plume(3)), b(plume(4));
    a.advance_to_frame(10);
    b.advance_to_frame(10);
    EXPECT_FALSE(bit_identical(a.particles(), b.particles()));
    // Not merely reordered: the first particle of the first emitter was born elsewhere.
    EXPECT_NE(sample_particle(plume(3).emitters[0], 3, 0, 0).position,
              sample_particle(plume(4).emitters[0], 4, 0, 0).position);
}

TEST(Simulator, ClockFramesAndPreroll) {
    Preset p = plume();
    p.timeline.preroll = 0.5;  // 24 steps = 12 frames at 24 fps, 2 substeps
    Simulator pre(p);
    EXPECT_EQ(pre.frame(), 0);
    EXPECT_EQ(pre.step_index(), 24u);
    EXPECT_DOUBLE_EQ(pre.time(), 0.5);
    // Frame 0 after a preroll is frame 12 without one.
    Simulator plain(plume());
    plain.advance_to_frame(12);
    EXPECT_TRUE(bit_identical(pre.particles(), plain.particles()));
    pre.step_frame();
    pre.step_frame();
    EXPECT_EQ(pre.frame(), 2);
    EXPECT_DOUBLE_EQ(pre.time(), 0.5 + 2.0 / 24.0);
    EXPECT_DOUBLE_EQ(pre.step_seconds(), 1.0 / 48.0);
    // A replay goes back to frame 0 after the preroll, not to time 0.
    pre.advance_to_frame(1);
    EXPECT_EQ(pre.frame(), 1);
    EXPECT_EQ(pre.step_index(), 26u);
}

TEST(Simulator, ParticlesDieAtTheirLifetime) {
    Preset p;
    p.timeline.fps = 10.0;
    p.timeline.substeps = 1;
    EmitterDesc e;
    e.bursts = {{0.0, 10}};
    e.lifetime = {1.05, 1.05};
    p.emitters.push_back(e);
    Simulator sim(p);
    sim.advance_to_frame(10);  // age 1.0 < 1.05
    EXPECT_EQ(sim.size(), 10u);
    sim.step_frame();  // age 1.1 >= 1.05
    EXPECT_EQ(sim.size(), 0u);

    // Mixed lifetimes: exactly the particles whose lifetime exceeds the age survive.
    e.lifetime = {0.2, 2.0};
    e.bursts = {{0.0, 500}};
    p.emitters = {e};
    Simulator mixed(p);
    float age = 0.0f;  // accumulated as the simulator does
    for (int f = 1; f <= 25; ++f) {
        mixed.step_frame();
        age += float(0.1);
        std::size_t alive = 0;
        for (std::uint64_t n = 0; n < 500; ++n) alive += float(sample_particle(e, 1, 0, n).lifetime) > age;
        ASSERT_EQ(mixed.size(), alive) << "frame " << f;
        for (std::size_t i = 0; i < mixed.size(); ++i)
            ASSERT_LT(mixed.particles().age[i], mixed.particles().lifetime[i]);
    }
    EXPECT_EQ(mixed.size(), 0u);
}

TEST(Simulator, RejectsTimelinesItCannotStep) {
    Preset p;
    p.timeline.fps = 0.0;
    EXPECT_THROW(Simulator{p}, std::invalid_argument);
    p.timeline.fps = 24.0;
    p.timeline.substeps = 0;
    EXPECT_THROW(Simulator{p}, std::invalid_argument);
    p.timeline.substeps = 1;
    p.timeline.preroll = -1.0;
    EXPECT_THROW(Simulator{p}, std::invalid_argument);
}

TEST(Simulator, BenchmarkRuns) {
    const double ms = benchmark_step_ms(2000, 3);
    EXPECT_GT(ms, 0.0);
    EXPECT_LT(ms, 1e4);
}

}  // namespace
}  // namespace brume
