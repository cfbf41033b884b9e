// Forces and the integrator against closed forms, the curl noise's divergence, and box collisions.
//
// The integrator is exact for the linear part of the force (constant accelerations, drag, wind), so
// motion under those forces must match the closed forms to float rounding alone: about one float
// ulp of the coordinates per step. The tolerances below allow 1e-6 relative per step over the run;
// a first-order (Euler) scheme would be off by g dt t / 2, i.e. centimetres, and fail.
#include "sim/forces.h"
#include "sim/noise.h"
#include "sim/rng.h"
#include "sim/simulator.h"

#include "test_scenes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

using testing::force;

// One particle from a point emitter at x0 with velocity v0, born at time 0, living forever.
Preset single_particle(dvec3 x0, dvec3 v0, std::vector<ForceDesc> forces, double fps = 24.0, int substeps = 2) {
    Preset p;
    p.timeline.fps = fps;
    p.timeline.substeps = substeps;
    EmitterDesc e;
    e.center = x0;
    e.bursts = {{0.0, 1}};
    const double speed = glm::length(v0);
    e.direction = speed > 0.0 ? v0 : dvec3{0.0, 1.0, 0.0};
    e.speed = {speed, speed};
    e.lifetime = {1e6, 1e6};
    p.emitters.push_back(e);
    p.forces = std::move(forces);
    return p;
}

dvec3 position(const Simulator& sim) {
    const Particles& p = sim.particles();
    return {p.x[0], p.y[0], p.z[0]};
}
dvec3 velocity(const Simulator& sim) {
    const Particles& p = sim.particles();
    return {p.vx[0], p.vy[0], p.vz[0]};
}

void expect_near(const dvec3& a, const dvec3& b, double tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

// ---------------------------------------------------------------------------------------------------
// The exponential Euler step

TEST(LinearStep, MatchesClosedFormsAcrossTheSeriesSwitch) {
    const double dt = 0.02;
    for (double k : {0.0, 1e-6, 0.0499, 0.05, 0.0501, 0.3, 2.0, 50.0, -0.5}) {
        const LinearStep s = make_linear_step(k, dt);
        const double e = std::exp(-k * dt);
        // Reference in long double through expm1, which keeps x - (1 - e^-x) accurate for tiny x.
        const long double x = (long double)k * dt, dl = dt;
        const long double phi1 = k == 0.0 ? dl : -std::expm1(-x) / (long double)k;
        const long double phi2 = k == 0.0 ? dl * dl / 2.0L : dl * dl * (x + std::expm1(-x)) / (x * x);
        EXPECT_NEAR(s.decay, e, 1e-7) << "k = " << k;
        EXPECT_NEAR(s.phi1, double(phi1), 1e-7 * dt) << "k = " << k;
        EXPECT_NEAR(s.phi2, double(phi2), 1e-6 * dt * dt) << "k = " << k;
    }
}

// ---------------------------------------------------------------------------------------------------
// Motion against closed forms

TEST(Integrator, BallisticMotionIsExact) {
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.0, -9.81, 0.0};
    const dvec3 x0{0.0, 1.0, 0.0}, v0{3.0, 6.0, -1.0};
    Simulator sim(single_particle(x0, v0, {gravity}));
    for (int f = 1; f <= 48; ++f) {
        sim.step_frame();
        const double t = f / 24.0;
        expect_near(position(sim), x0 + v0 * t + 0.5 * gravity.vector * t * t, 1e-6 * 2 * f * 10.0, "x(t)");
        expect_near(velocity(sim), v0 + gravity.vector * t, 1e-6 * 2 * f * 10.0, "v(t)");
    }
}

TEST(Integrator, LinearDragDecaysExponentially) {
    ForceDesc drag = force(ForceKind::Drag);
    drag.strength = 1.5;
    const dvec3 x0{1.0, 2.0, 3.0}, v0{4.0, -2.0, 1.0};
    Simulator sim(single_particle(x0, v0, {drag}, 30.0, 1));
    for (int f = 1; f <= 90; ++f) {
        sim.step_frame();
        const double t = f / 30.0;
        const double e = std::exp(-1.5 * t);
        expect_near(velocity(sim), v0 * e, 1e-6 * f * 5.0, "v0 exp(-k t)");
        expect_near(position(sim), x0 + v0 * (1.0 - e) / 1.5, 1e-6 * f * 5.0, "x(t)");
    }
}

TEST(Integrator, WindRelaxesTowardTheWindVelocity) {
    ForceDesc wind = force(ForceKind::Wind);
    wind.vector = {2.0, 0.0, -1.0};
    wind.strength = 0.8;
    const dvec3 x0{0.0}, v0{0.0, 3.0, 0.0}, w = wind.vector;
    Simulator sim(single_particle(x0, v0, {wind}, 24.0, 2));
    for (int f = 1; f <= 120; ++f) {
        sim.step_frame();
        const double t = f / 24.0;
        const double e = std::exp(-0.8 * t);
        expect_near(velocity(sim), w + (v0 - w) * e, 2e-6 * f * 5.0, "w + (v0 - w) exp(-s t)");
        expect_near(position(sim), x0 + w * t + (v0 - w) * (1.0 - e) / 0.8, 2e-6 * f * 10.0, "x(t)");
    }
    expect_near(velocity(sim), w, 0.1, "near the wind after 5 s");
}

TEST(Integrator, GravityBuoyancyAndDragTogether) {
    // b = gravity + buoyancy, k = drag: v = b/k + (v0 - b/k) exp(-k t), terminal velocity b/k.
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.5, -9.81, 0.0};
    ForceDesc buoyancy = force(ForceKind::Buoyancy);
    buoyancy.strength = 12.0;
    ForceDesc drag = force(ForceKind::Drag);
    drag.strength = 0.7;
    const dvec3 x0{0.0, 0.5, 0.0}, v0{0.0, 0.0, 1.0};
    const dvec3 b = gravity.vector + dvec3{0.0, 12.0, 0.0};
    Simulator sim(single_particle(x0, v0, {gravity, buoyancy, drag}, 24.0, 2));
    sim.advance_to_frame(72);
    const double t = 3.0, k = 0.7, e = std::exp(-k * t);
    expect_near(velocity(sim), b / k + (v0 - b / k) * e, 1e-4, "v(t)");
    expect_near(position(sim), x0 + b / k * t + (v0 - b / k) * (1.0 - e) / k, 1e-4, "x(t)");
}

TEST(Forces, DoubleAccelerationFollowsThePresetComments) {
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.1, -9.8, 0.2};
    ForceDesc buoyancy = force(ForceKind::Buoyancy);
    buoyancy.strength = 3.0;
    ForceDesc wind = force(ForceKind::Wind);
    wind.vector = {1.0, 2.0, 3.0};
    wind.strength = 0.5;
    ForceDesc drag = force(ForceKind::Drag);
    drag.strength = 0.25;
    const ForceField field({gravity, buoyancy, wind, drag}, 1);
    const dvec3 v{-1.0, 0.5, 2.0};
    const dvec3 expected = gravity.vector + dvec3{0.0, 3.0, 0.0} + 0.5 * (wind.vector - v) - 0.25 * v;
    expect_near(field.acceleration({1.0, 2.0, 3.0}, v, 4.0), expected, 1e-12, "a(x, v, t)");
    EXPECT_DOUBLE_EQ(field.linear_rate(), 0.75);
}

// ---------------------------------------------------------------------------------------------------
// Vortex

TEST(Forces, VortexIsTangentialWithTheStatedMagnitude) {
    ForceDesc vortex = force(ForceKind::Vortex);
    vortex.center = {1.0, 0.0, 2.0};
    vortex.axis = {0.0, 2.0, 0.0};  // not unit
    vortex.strength = 3.0;
    vortex.radius = 0.5;
    const ForceField field({vortex}, 1);
    const dvec3 w{0.0, 1.0, 0.0};
    for (const dvec3& x : {dvec3{2.0, 0.0, 2.0}, dvec3{1.0, 5.0, 4.0}, dvec3{-0.3, -2.0, 1.1}}) {
        const dvec3 a = field.acceleration(x, dvec3{0.0}, 0.0);
        dvec3 r = x - vortex.center;
        r -= glm::dot(r, w) * w;
        EXPECT_NEAR(glm::dot(a, r), 0.0, 1e-12);  // tangential
        EXPECT_NEAR(glm::dot(a, w), 0.0, 1e-12);  // no axial part
        const double rr = glm::dot(r, r);
        EXPECT_NEAR(glm::length(a), 3.0 * std::sqrt(rr) / (rr + 0.25), 1e-12);
        EXPECT_GT(glm::dot(glm::cross(r, a), w), 0.0);  // counterclockwise about +axis
    }
    // The float loop agrees.
    const float x[3] = {2.0f, 1.0f, -0.3f}, y[3] = {0.0f, 5.0f, -2.0f}, z[3] = {2.0f, 4.0f, 1.1f};
    float ax[3], ay[3], az[3];
    field.accelerations(x, y, z, 3, nullptr, ax, ay, az);
    for (int i = 0; i < 3; ++i) {
        const dvec3 a = field.acceleration({x[i], y[i], z[i]}, dvec3{0.0}, 0.0);
        EXPECT_NEAR(ax[i], a.x, 1e-6);
        EXPECT_NEAR(ay[i], a.y, 1e-6);
        EXPECT_NEAR(az[i], a.z, 1e-6);
    }
}

// ---------------------------------------------------------------------------------------------------
// Turbulence

ForceDesc turbulence(int octaves = 3) {
    ForceDesc f = force(ForceKind::Turbulence);
    f.strength = 2.0;
    f.scale = 0.7;
    f.speed = 0.5;
    f.octaves = octaves;
    return f;
}

dvec3 random_point(std::uint64_t i, double extent) {
    const std::uint64_t key = rng::hash(77, i);
    return extent * (2.0 * dvec3{rng::uniform(key, 0), rng::uniform(key, 1), rng::uniform(key, 2)} - 1.0);
}

// Central differences of a field: divergence, and the Jacobian's Frobenius norm to compare it with.
template <class F>
void divergence_and_gradient(F&& u, const dvec3& x, double h, double& div, double& grad) {
    div = 0.0;
    grad = 0.0;
    for (int a = 0; a < 3; ++a) {
        dvec3 dx{0.0};
        dx[a] = h;
        const dvec3 d = (u(x + dx) - u(x - dx)) / (2.0 * h);
        div += d[a];
        grad += glm::dot(d, d);
    }
    grad = std::sqrt(grad);
}

TEST(Turbulence, IsDivergenceFree) {
    const ForceField field({turbulence()}, 5);
    double worst = 0.0, mean_grad = 0.0;
    for (std::uint64_t i = 0; i < 200; ++i) {
        const dvec3 x = random_point(i, 10.0);
        const double t = 0.37 * double(i);
        double div, grad;
        // h small against the finest wavelength (about 1 / (0.7 * 4) units): truncation ~ (k h)^2.
        divergence_and_gradient([&](const dvec3& p) { return field.acceleration(p, dvec3{0.0}, t); }, x, 1e-5,
                                div, grad);
        worst = std::max(worst, std::abs(div) / grad);
        mean_grad += grad / 200.0;
    }
    EXPECT_LT(worst, 1e-6);
    EXPECT_GT(mean_grad, 1.0);  // the field really varies: strength 2 at wave numbers of several rad/unit

    // The test can tell: the same field with its components permuted, as smooth and as strong but not
    // a curl, has a divergence comparable to its gradient.
    double ratio = 0.0;
    for (std::uint64_t i = 0; i < 200; ++i) {
        double div, grad;
        const auto permuted = [&](const dvec3& p) {
            const dvec3 a = field.acceleration(p, dvec3{0.0}, 0.0);
            return dvec3{a.y, a.z, a.x};
        };
        divergence_and_gradient(permuted, random_point(i, 10.0), 1e-5, div, grad);
        ratio += std::abs(div) / grad / 200.0;
    }
    EXPECT_GT(ratio, 0.1);
}

TEST(Turbulence, IsTheCurlOfItsPotential) {
    const CurlNoise noise(9, {2, 2.0, 0.5, 1.3, 1.0});
    for (std::uint64_t i = 0; i < 50; ++i) {
        const dvec3 x = random_point(i, 5.0);
        const double tau = 0.1 * double(i), h = 1e-5;
        dvec3 d[3];
        for (int a = 0; a < 3; ++a) {
            dvec3 dx{0.0};
            dx[a] = h;
            d[a] = (noise.potential(x + dx, tau) - noise.potential(x - dx, tau)) / (2.0 * h);  // d psi / d x_a
        }
        const dvec3 curl{d[1].z - d[2].y, d[2].x - d[0].z, d[0].y - d[1].x};
        const dvec3 u = noise.velocity(x, tau);
        expect_near(curl, u, 1e-7 * (1.0 + glm::length(u)), "curl psi");
    }
}

// Octaves a gain of 0 silences change nothing, near the origin or 60 units from it; and the coarse
// octaves keep varying in space however fine the finest is. One position limit for all octaves, the
// finest's, clamped every particle past it for the coarse octaves too: 16 octaves at lacunarity 16 made
// the field one constant everywhere (a clump drifted rigidly), and 16 octaves at lacunarity 2 froze it
// past 37 units.
TEST(Turbulence, FineOctavesLeaveTheCoarseOnesAlone) {
    const CurlNoise one(9, {1, 2.0, 0.5, 1.0, 1.0});
    const CurlNoise silenced(9, {16, 16.0, 0.0, 1.0, 1.0});
    std::vector<float> phases_one(one.mode_count()), phases_silenced(silenced.mode_count());
    one.phases(3.5, phases_one.data());
    silenced.phases(3.5, phases_silenced.data());
    constexpr int n = 40;
    std::vector<float> x(n), y(n), z(n);
    for (int i = 0; i < n; ++i) {
        const dvec3 p = random_point(std::uint64_t(i), 5.0) + (i < n / 2 ? dvec3{0.0} : dvec3{60.0, -60.0, 60.0});
        x[std::size_t(i)] = float(p.x), y[std::size_t(i)] = float(p.y), z[std::size_t(i)] = float(p.z);
    }
    std::vector<float> a(3 * n, 0.0f), b(3 * n, 0.0f);
    one.accumulate(x.data(), y.data(), z.data(), n, phases_one.data(), a.data(), a.data() + n, a.data() + 2 * n);
    silenced.accumulate(x.data(), y.data(), z.data(), n, phases_silenced.data(), b.data(), b.data() + n, b.data() + 2 * n);
    EXPECT_EQ(a, b);
    // Sixteen octaves at lacunarity 2, gain 0.5: past 37 units the field still varies from point to point.
    const CurlNoise fine(9, {16, 2.0, 0.5, 1.0, 1.0});
    std::vector<float> phases_fine(fine.mode_count());
    fine.phases(3.5, phases_fine.data());
    std::vector<float> c(3 * n, 0.0f);
    fine.accumulate(x.data(), y.data(), z.data(), n, phases_fine.data(), c.data(), c.data() + n, c.data() + 2 * n);
    int distinct = 0;
    for (int i = n / 2 + 1; i < n; ++i) distinct += c[std::size_t(i)] != c[std::size_t(n / 2)];
    EXPECT_EQ(distinct, n / 2 - 1);
}

TEST(Turbulence, FloatLoopMatchesTheDoubleFieldAndStaysSolenoidal) {
    const ForceField field({turbulence()}, 5);
    const double t = 12.25;
    std::vector<float> phases(field.phase_count());
    field.phases(t, phases.data());
    constexpr int n = 300;
    std::vector<float> x(n), y(n), z(n), ax(n), ay(n), az(n);
    for (int i = 0; i < n; ++i) {
        const dvec3 p = random_point(std::uint64_t(i), 20.0);
        x[std::size_t(i)] = float(p.x), y[std::size_t(i)] = float(p.y), z[std::size_t(i)] = float(p.z);
    }
    field.accelerations(x.data(), y.data(), z.data(), n, phases.data(), ax.data(), ay.data(), az.data());
    double rms = 0.0, worst = 0.0;
    for (int i = 0; i < n; ++i) {
        const std::size_t j = std::size_t(i);
        const dvec3 ref = field.acceleration({x[j], y[j], z[j]}, dvec3{0.0}, t);
        rms += glm::dot(ref, ref) / n;
        worst = std::max(worst, glm::length(dvec3{ax[j], ay[j], az[j]} - ref));
    }
    rms = std::sqrt(rms);
    // Float positions near 20 units carry 2e-6 of rounding, a phase error of 3e-5 rad at the highest
    // wave numbers; measured 1e-5 of the RMS, so 1e-4 leaves a margin of 10.
    EXPECT_LT(worst, 1e-4 * rms);

    // Divergence of the float field by finite differences, with h large enough for float rounding
    // (about 1e-5 |u| / (2 h |grad u|) = 2e-4) and small enough for truncation ((k h)^2 / 6 at the
    // highest wave number, 5e-3 for that octave alone); measured 8e-4. A field that is not
    // solenoidal scores about 0.5 (the permuted field above).
    const float h = 0.01f;
    double ratio = 0.0;
    for (int i = 0; i < 50; ++i) {
        const dvec3 c = random_point(std::uint64_t(i), 20.0);
        float px[6], py[6], pz[6], qx[6], qy[6], qz[6];
        for (int k = 0; k < 6; ++k) {
            px[k] = float(c.x), py[k] = float(c.y), pz[k] = float(c.z);
            float* axis[3] = {&px[k], &py[k], &pz[k]};
            *axis[k / 2] += (k % 2 ? -h : h);
        }
        field.accelerations(px, py, pz, 6, phases.data(), qx, qy, qz);
        // Divided by the float positions' actual spacing, which rounding makes differ from 2 h.
        const double div = (double(qx[0]) - qx[1]) / (double(px[0]) - px[1]) +
                           (double(qy[2]) - qy[3]) / (double(py[2]) - py[3]) +
                           (double(qz[4]) - qz[5]) / (double(pz[4]) - pz[5]);
        double div_ref, grad;
        divergence_and_gradient([&](const dvec3& p) { return field.acceleration(p, dvec3{0.0}, t); }, c, 1e-5,
                                div_ref, grad);
        ratio = std::max(ratio, std::abs(div) / grad);
    }
    EXPECT_LT(ratio, 3e-3);
}

TEST(Turbulence, StrengthOctavesAndTimeEvolution) {
    // One octave has RMS speed `strength`; sum over octaves of gain^o squared for more.
    auto rms_of = [](const ForceField& f, double t) {
        double s = 0.0;
        for (std::uint64_t i = 0; i < 4000; ++i) {
            const dvec3 a = f.acceleration(random_point(i, 50.0), dvec3{0.0}, t);
            s += glm::dot(a, a) / 4000.0;
        }
        return std::sqrt(s);
    };
    const ForceField one({turbulence(1)}, 5);
    EXPECT_NEAR(rms_of(one, 0.0), 2.0, 0.3);
    const ForceField three({turbulence(3)}, 5);
    EXPECT_NEAR(rms_of(three, 0.0), 2.0 * std::sqrt(1.0 + 0.25 + 0.0625), 0.35);

    // speed > 0: the field changes with time; speed 0: it does not.
    const dvec3 x{1.0, 2.0, 3.0};
    EXPECT_GT(glm::length(one.acceleration(x, dvec3{0.0}, 0.0) - one.acceleration(x, dvec3{0.0}, 3.0)), 0.1);
    ForceDesc still = turbulence(1);
    still.speed = 0.0;
    const ForceField frozen({still}, 5);
    EXPECT_EQ(frozen.acceleration(x, dvec3{0.0}, 0.0), frozen.acceleration(x, dvec3{0.0}, 3.0));
    // Different seeds, different fields; two turbulence forces in one preset differ too.
    const ForceField other({turbulence(1)}, 6);
    EXPECT_GT(glm::length(one.acceleration(x, dvec3{0.0}, 0.0) - other.acceleration(x, dvec3{0.0}, 0.0)), 1e-3);
}

// ---------------------------------------------------------------------------------------------------
// Collisions

Box box(dvec3 lo, dvec3 hi) { return Box{lo, hi, dvec3{0.5}}; }

bool strictly_inside(const Box& b, const dvec3& p) {
    return p.x > b.min.x && p.x < b.max.x && p.y > b.min.y && p.y < b.max.y && p.z > b.min.z && p.z < b.max.z;
}

TEST(Collisions, PushOutThroughTheNearestFaceRemovingInwardVelocity) {
    const BoxObstacles boxes({box({-5.0, -1.0, -5.0}, {5.0, 0.1, 5.0})});  // 0.1: not a float
    float x = 1.0f, y = 0.05f, z = 2.0f, vx = 0.3f, vy = -2.0f, vz = 0.4f;
    ASSERT_TRUE(boxes.inside(x, y, z));
    ASSERT_TRUE(boxes.push_out(x, y, z, vx, vy, vz));
    EXPECT_FALSE(strictly_inside(box({-5.0, -1.0, -5.0}, {5.0, 0.1, 5.0}), {x, y, z}));
    EXPECT_GE(double(y), 0.1);
    EXPECT_LT(double(y), 0.1 + 1e-7);  // onto the face, not beyond it
    EXPECT_EQ(x, 1.0f);
    EXPECT_EQ(z, 2.0f);
    EXPECT_EQ(vy, 0.0f);  // inward normal velocity removed
    EXPECT_EQ(vx, 0.3f);  // tangential kept (no friction)
    EXPECT_EQ(vz, 0.4f);

    // Pushed down through a min face that is not a float either: it must end at or below 0.1.
    const Box raised = box({-1.0, 0.1, -1.0}, {1.0, 2.0, 1.0});
    const BoxObstacles high({raised});
    x = 0.0f, y = 0.15f, z = 0.0f, vx = 0.0f, vy = 1.0f, vz = 0.0f;
    ASSERT_TRUE(high.push_out(x, y, z, vx, vy, vz));
    EXPECT_FALSE(strictly_inside(raised, {x, y, z}));
    EXPECT_LE(double(y), 0.1);
    EXPECT_EQ(vy, 0.0f);

    // Outward velocity is kept; the nearest face here is x = -5.
    x = -4.99f, y = -0.5f, z = 0.0f, vx = -1.0f, vy = 0.5f, vz = 0.0f;
    ASSERT_TRUE(boxes.push_out(x, y, z, vx, vy, vz));
    EXPECT_EQ(x, -5.0f);
    EXPECT_EQ(vx, -1.0f);
    EXPECT_EQ(vy, 0.5f);

    // Outside and on the surface: untouched.
    x = 1.0f, y = 0.2f, z = 0.0f, vx = 0.0f, vy = -1.0f, vz = 0.0f;
    EXPECT_FALSE(boxes.inside(x, y, z));
    EXPECT_FALSE(boxes.inside(1.0f, 0.100000001f, 0.0f));
    EXPECT_TRUE(boxes.push_out(x, y, z, vx, vy, vz));
    EXPECT_EQ(y, 0.2f);
    EXPECT_EQ(vy, -1.0f);
}

TEST(Collisions, OverlappingBoxesPushIntoTheUnionsOutside) {
    // Two overlapping boxes: leaving the first through its nearest face lands inside the second.
    const std::vector<Box> bs = {box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}), box({0.9, 0.0, 0.0}, {3.0, 1.0, 1.0})};
    const BoxObstacles boxes(bs);
    float x = 0.95f, y = 0.5f, z = 0.5f, vx = 1.0f, vy = 0.0f, vz = 0.0f;
    ASSERT_TRUE(boxes.push_out(x, y, z, vx, vy, vz));
    for (const Box& b : bs) EXPECT_FALSE(strictly_inside(b, {x, y, z}));
}

// A fountain raining onto a ground box, a block, two overlapping blocks and a thin plate, with
// turbulence stirring it, and an emitter partly inside a box: after every step, no particle centre
// is strictly inside any box.
TEST(Collisions, ParticlesStayOutOfBoxesOverALongRun) {
    Preset p;
    p.timeline.fps = 24.0;
    p.timeline.substeps = 3;
    p.timeline.max_particles = 5000;
    p.scene.boxes = {box({-10.0, -1.0, -10.0}, {10.0, 0.0, 10.0}), box({0.5, 0.0, -0.5}, {1.5, 1.0, 0.5}),
                     box({-1.5, 0.0, -1.0}, {-0.5, 0.7, 0.0}), box({-1.0, 0.0, -0.5}, {0.0, 1.2, 0.5}),
                     box({-2.0, 1.5, -2.0}, {2.0, 1.55, 2.0})};
    EmitterDesc e;
    e.shape = EmitterShape::Sphere;
    e.center = {0.0, 1.6, 0.0};  // overlaps the plate: some births are inside it
    e.radius = 0.3;
    e.rate = 300.0;
    e.direction = {0.0, 1.0, 0.0};
    e.speed = {2.0, 4.0};
    e.cone_deg = 60.0;
    e.jitter = 0.5;
    e.lifetime = {3.0, 6.0};
    p.emitters.push_back(e);
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.0, -9.81, 0.0};
    ForceDesc turb = turbulence(2);
    turb.strength = 6.0;
    p.forces = {gravity, turb};
    Simulator sim(p);
    std::size_t checked = 0, low = 0;
    for (int f = 0; f < 240; ++f) {
        sim.step_frame();
        const Particles& q = sim.particles();
        for (std::size_t i = 0; i < q.size(); ++i) {
            const dvec3 x{q.x[i], q.y[i], q.z[i]};
            for (const Box& b : p.scene.boxes)
                ASSERT_FALSE(strictly_inside(b, x)) << "frame " << f << " particle " << i;
            low += x.y < 0.05;
            ++checked;
        }
    }
    EXPECT_GT(checked, 100000u);
    EXPECT_GT(low, 1000u);  // many particles did reach the ground: the boxes were exercised
}

}  // namespace
}  // namespace brume
