// The reference renderer against closed forms of the light model (the intersecting homogeneous media of
// Barta & Kovács, "Order Independent Transparency with Per-Pixel Linked Lists", section 3.5, made
// robust as render/reference.h states), and its invariances:
// sphere order, binning and thread count may not change a single bit.
#include "render/reference.h"

#include "test_scenes.h"

#include "sim/camera_rays.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;

// Lighting with distinct channels so a swapped channel shows.
Scene base_scene() {
    Scene s;
    s.lighting.ambient = {0.21, 0.33, 0.45};
    s.lighting.sun = {1.3, 0.9, 0.6};
    s.lighting.sun_direction = {-0.4, -1.0, -0.3};
    s.lighting.background = {0.07, 0.11, 0.02};
    s.render.min_transmittance = 1e-4;
    return s;
}

using testing::sphere;

Box box(dvec3 lo, dvec3 hi, dvec3 radiance) {
    Box b;
    b.min = lo;
    b.max = hi;
    b.radiance = radiance;
    return b;
}

// L_s, written out independently of the renderer.
dvec3 source(const Scene& s, const dvec3& dir) { return testing::source_radiance(s, dir); }

// Front-to-back compositing of homogeneous segments, eq. 3 as printed (fine away from tiny extinction).
struct Segment {
    double length;
    double sigma_t;
    dvec3 albedo;
};
dvec3 composite(const std::vector<Segment>& segments, const dvec3& ls, const dvec3& behind) {
    dvec3 l(0.0);
    double t = 1.0;
    for (const Segment& s : segments) {
        const double seg_t = std::exp(-s.sigma_t * s.length);
        l += t * s.albedo * ls * (1.0 - seg_t);
        t *= seg_t;
    }
    return l + t * behind;
}

void expect_near3(const dvec3& got, const dvec3& want, double tol, const char* what = "") {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tol) << what << " channel " << c;
}

void expect_finite(const dvec3& v, const char* what) {
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(v[c])) << what << " channel " << c << " = " << v[c];
}

bool bit_identical(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

std::size_t count_differing(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < std::min(a.rgb.size(), b.rgb.size()); ++k)
        n += std::memcmp(&a.rgb[k], &b.rgb[k], sizeof(float)) != 0;
    return n;
}

const dvec3 kDown{0.0, 0.0, -1.0};

TEST(Reference, RayThroughSphereCentre) {
    Scene s = base_scene();
    const dvec3 c{0.3, -0.2, 0.1};
    const double r = 1.5, tau = 0.7;
    const dvec3 a{0.9, 0.5, 0.2};
    s.spheres = {sphere(c, r, tau, a)};
    const dvec3 ls = source(s, kDown);
    const double tr = std::exp(-2.0 * tau * r);
    const dvec3 want = a * ls * (1.0 - tr) + tr * s.lighting.background;
    expect_near3(reference_radiance(s, c + dvec3(0, 0, 6), kDown), want, 1e-13);

    // The same ray as the single pixel of a 1x1 camera: rendering samples the pixel centre.
    s.camera.position = c + dvec3(0, 0, 6);
    s.camera.look_at = c;
    s.camera.width = s.camera.height = 1;
    const Image img = render_reference(s);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(img.pixel(0, 0)[ch], want[ch], 1e-6 * want[ch]);
}

TEST(Reference, EyeInsideSphereCountsFromZero) {
    Scene s = base_scene();
    const dvec3 a{0.4, 0.8, 0.6};
    s.spheres = {sphere({0, 0, 0}, 1.5, 0.9, a)};
    const dvec3 eye{0, 0, 0.4};
    const dvec3 up{0, 0, 1};
    expect_near3(reference_radiance(s, eye, kDown), composite({{1.9, 0.9, a}}, source(s, kDown), s.lighting.background),
                 1e-13, "looking through the far side");
    expect_near3(reference_radiance(s, eye, up), composite({{1.1, 0.9, a}}, source(s, up), s.lighting.background),
                 1e-13, "looking through the near side");
}

TEST(Reference, TwoOverlappingSpheresIntersectAsMedia) {
    Scene s = base_scene();
    const dvec3 a1{0.9, 0.2, 0.4}, a2{0.1, 0.7, 0.95};
    const double t1 = 0.8, t2 = 1.3;
    s.spheres = {sphere({0, 0, 0}, 1.0, t1, a1), sphere({0, 0, -1.2}, 1.0, t2, a2)};
    // From z = 5 down: A alone on [4, 5.2], both on [5.2, 6], B alone on [6, 7.2].
    const dvec3 mixed = (t1 * a1 + t2 * a2) / (t1 + t2);
    const dvec3 want = composite({{1.2, t1, a1}, {0.8, t1 + t2, mixed}, {1.2, t2, a2}}, source(s, kDown),
                                 s.lighting.background);
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), want, 1e-13);
    std::swap(s.spheres[0], s.spheres[1]);
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), want, 1e-13, "listed in the other order");
}

TEST(Reference, NestedSpheres) {
    Scene s = base_scene();
    const dvec3 a1{0.9, 0.2, 0.4}, a2{0.3, 0.6, 1.0};
    const double t1 = 0.5, t2 = 2.0;
    s.spheres = {sphere({0, 0, 0}, 2.0, t1, a1), sphere({0, 0, 0}, 0.8, t2, a2)};
    const dvec3 mixed = (t1 * a1 + t2 * a2) / (t1 + t2);
    const dvec3 want = composite({{1.2, t1, a1}, {1.6, t1 + t2, mixed}, {1.2, t1, a1}}, source(s, kDown),
                                 s.lighting.background);
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), want, 1e-13);
}

TEST(Reference, SumsReturnToExactlyZeroWhenTheLastMediumEnds) {
    // Entering 0.1, 0.2, 0.3 and leaving in reverse leaves 2.8e-17 in a running sum; across a gap of 1e8
    // that residue would dim everything behind by about 3e-9.
    Scene s = base_scene();
    s.render.min_transmittance = 0.0;
    const dvec3 a{0.9, 0.5, 0.2}, far_a{0.3, 0.6, 0.9};
    s.spheres = {sphere({0, 0, 0}, 1.5, 0.1, a), sphere({0, 0, 0}, 1.0, 0.2, a), sphere({0, 0, 0}, 0.5, 0.3, a),
                 sphere({0, 0, -1e8}, 1.0, 1.0, far_a)};
    const dvec3 ls = source(s, kDown);
    const dvec3 want = composite({{0.5, 0.1, a}, {0.5, 0.3, a}, {1.0, 0.6, a}, {0.5, 0.3, a}, {0.5, 0.1, a},
                                  {1e8 - 1.0 - 1.5, 0.0, dvec3(0.0)}, {2.0, 1.0, far_a}},
                                 ls, s.lighting.background);
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), want, 1e-13);
}

TEST(Reference, CoincidentSpheresEqualOneWithSummedExtinction) {
    Scene two = base_scene();
    const dvec3 c{0.2, 0.1, -0.3};
    const dvec3 a1{0.9, 0.2, 0.4}, a2{0.3, 0.6, 1.0};
    const double t1 = 0.6, t2 = 1.7;
    two.spheres = {sphere(c, 1.1, t1, a1), sphere(c, 1.1, t2, a2)};
    Scene one = two;
    one.spheres = {sphere(c, 1.1, t1 + t2, (t1 * a1 + t2 * a2) / (t1 + t2))};

    two.camera.position = {0, 0.5, 5};
    two.camera.look_at = c;
    two.camera.width = 24;
    two.camera.height = 18;
    const CameraRays rays = make_camera_rays(two.camera);
    int hits = 0;
    for (int j = 0; j < rays.height; ++j) {
        for (int i = 0; i < rays.width; ++i) {
            const dvec3 d = rays.pixel_direction(i, j);
            const dvec3 l2 = reference_radiance(two, rays.eye, d);
            const dvec3 l1 = reference_radiance(one, rays.eye, d);
            expect_near3(l2, l1, 1e-14);
            hits += l1 != two.lighting.background;
        }
    }
    EXPECT_GT(hits, 50) << "the sphere must cover part of the view for this test to mean anything";
}

TEST(Reference, BoxCutsSphereExactly) {
    Scene s = base_scene();
    const dvec3 a{0.8, 0.8, 0.3};
    const dvec3 box_l{0.1, 0.7, 0.3};
    s.spheres = {sphere({0, 0, 0}, 1.0, 0.9, a)};
    const dvec3 ls = source(s, kDown);

    // The box's front face at z = 0.25 lies inside the sphere: the chord is [4, 4.75].
    s.boxes = {box({-2, -2, -3}, {2, 2, 0.25}, box_l)};
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), composite({{0.75, 0.9, a}}, ls, box_l), 1e-13, "cut");

    s.boxes = {box({-2, -2, 1.5}, {2, 2, 2.0}, box_l)};
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), box_l, 0.0, "in front");

    s.boxes = {box({-2, -2, -5}, {2, 2, -3}, box_l)};
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), composite({{2.0, 0.9, a}}, ls, box_l), 1e-13, "behind");

    // The nearer of two boxes wins whatever their order.
    const dvec3 other{0.5, 0.1, 0.9};
    s.boxes = {box({-2, -2, -5}, {2, 2, -3}, box_l), box({-1, -1, -2}, {1, 1, -1.5}, other)};
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), composite({{2.0, 0.9, a}}, ls, other), 1e-13, "nearest");
}

TEST(Reference, EyeInsideBoxSeesItsRadiance) {
    Scene s = base_scene();
    const dvec3 box_l{0.3, 0.2, 0.1};
    s.boxes = {box({-1, -1, -1}, {1, 1, 1}, box_l)};
    s.spheres = {sphere({0, 0, 0}, 3.0, 1.0, {1, 1, 1})};
    for (const dvec3& d : {kDown, dvec3(1, 0, 0), glm::normalize(dvec3(1, 2, 3))})
        EXPECT_EQ(reference_radiance(s, {0.2, 0.3, -0.1}, d), box_l);
}

TEST(Reference, TangentAndGrazingRaysStayFinite) {
    Scene s = base_scene();
    const dvec3 a{0.6, 0.7, 0.8};
    s.spheres = {sphere({0, 0, 0}, 1.0, 2.0, a)};
    const dvec3 bg = s.lighting.background;
    const dvec3 ls = source(s, kDown);

    EXPECT_EQ(reference_radiance(s, {1, 0, 5}, kDown), bg) << "an exact tangent has a zero-length chord";
    EXPECT_EQ(reference_radiance(s, {1 + 1e-12, 0, 5}, kDown), bg);
    const double x = 1 - 1e-9;
    const double chord = 2.0 * std::sqrt(1.0 - x * x);
    expect_near3(reference_radiance(s, {x, 0, 5}, kDown), composite({{chord, 2.0, a}}, ls, bg), 1e-12, "grazing");
    for (int k = -50; k <= 50; ++k) {
        const dvec3 o{1.0 + k * 1e-17, 0.0, 5.0};
        expect_finite(reference_radiance(s, o, kDown), "near tangent");
        const dvec3 d = glm::normalize(dvec3(k * 1e-13, 0.0, -1.0));
        expect_finite(reference_radiance(s, {1, 0, 5}, d), "tilted tangent");
    }

    // Rays lying in a box's face planes: the parallel slab must not produce 0 * inf.
    Scene b = base_scene();
    const dvec3 box_l{0.9, 0.1, 0.4};
    b.boxes = {box({-1, -1, -1}, {1, 1, 1}, box_l)};
    EXPECT_EQ(reference_radiance(b, {-1, 0, 5}, kDown), box_l) << "in the x = min face plane (closed box)";
    EXPECT_EQ(reference_radiance(b, {1, 1, 5}, kDown), box_l) << "along an edge";
    EXPECT_EQ(reference_radiance(b, {1 + 1e-15, 0, 5}, kDown), b.lighting.background) << "just outside";
    EXPECT_EQ(reference_radiance(b, {-5, 1, 0}, dvec3(1, 0, 0)), box_l) << "in the y = max face plane";
    EXPECT_EQ(reference_radiance(b, {-5, 2, 0}, dvec3(1, 0, 0)), b.lighting.background) << "parallel, outside";
}

TEST(Reference, TinyExtinctionHasNoCancellation) {
    Scene s = base_scene();
    s.lighting.background = dvec3(0.0);  // leave only the scattered term, whose relative error we check
    const dvec3 a{0.5, 0.75, 1.0};
    // x = 2e-10 makes 1 - exp(-x) lose about 1e-6 relative: this tolerance catches it.
    for (const double tau : {1e-6, 1e-10}) {
        s.spheres = {sphere({0, 0, 0}, 1.0, tau, a)};
        const double x = 2.0 * tau;
        const double one_minus_t = x - x * x / 2.0 + x * x * x / 6.0 - x * x * x * x / 24.0;
        const dvec3 want = a * source(s, kDown) * one_minus_t;
        const dvec3 got = reference_radiance(s, {0, 0, 5}, kDown);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9 * want[c]) << "tau " << tau;
    }
}

TEST(Reference, DistantSmallSphereHasNoCancellation) {
    // b^2 - c would cancel to about 1e-6 here, the size of r^2 itself.
    Scene s = base_scene();
    const dvec3 a{0.3, 0.6, 0.9};
    const double r = 1e-3, tau = 500.0;
    s.spheres = {sphere({0, 0, -1e5}, r, tau, a)};
    const dvec3 ls = source(s, kDown);
    for (const double p : {0.0, 0.5e-3, 0.9e-3}) {
        const double chord = 2.0 * std::sqrt(r * r - p * p);
        expect_near3(reference_radiance(s, {p, 0, 0}, kDown), composite({{chord, tau, a}}, ls, s.lighting.background),
                     1e-7, "offset from the centre line");  // endpoints near 1e5 carry ~1e-11 each
    }
}

TEST(Reference, HugeExtinctionIsOpaqueAndFinite) {
    Scene s = base_scene();
    const dvec3 a{0.5, 0.75, 1.0};
    s.spheres = {sphere({0, 0, 0}, 1.0, 1e4, a)};
    for (const double min_t : {1e-4, 0.0}) {
        s.render.min_transmittance = min_t;
        const dvec3 got = reference_radiance(s, {0, 0, 5}, kDown);
        expect_finite(got, "outside");
        expect_near3(got, a * source(s, kDown), 1e-12, "outside");
        const dvec3 inside = reference_radiance(s, {0, 0, 0.5}, kDown);
        expect_finite(inside, "inside");
        expect_near3(inside, a * source(s, kDown), 1e-12, "inside");
    }
}

TEST(Reference, RayleighPhaseAtZeroAndNinetyDegrees) {
    Scene s = base_scene();
    s.lighting.sun_direction = {0.3, -1.0, 0.2};  // not unit: the renderer normalises it
    s.lighting.background = dvec3(0.0);
    s.spheres = {sphere({1, 2, 3}, 1.0, 1e4, dvec3(1.0))};  // opaque white: L = L_s
    const dvec3 sun = glm::normalize(s.lighting.sun_direction);
    const dvec3 amb = s.lighting.ambient, l_sun = s.lighting.sun;
    const dvec3 side = glm::normalize(glm::cross(sun, dvec3(1, 0, 0)));
    const dvec3 c{1, 2, 3};
    expect_near3(reference_radiance(s, c - 5.0 * sun, sun), amb + l_sun * (6.0 / (16.0 * kPi)), 1e-12, "0 deg");
    expect_near3(reference_radiance(s, c + 5.0 * sun, -sun), amb + l_sun * (6.0 / (16.0 * kPi)), 1e-12, "180 deg");
    expect_near3(reference_radiance(s, c - 5.0 * side, side), amb + l_sun * (3.0 / (16.0 * kPi)), 1e-12, "90 deg");
}

TEST(Reference, EarlyStopDropsEverythingBehind) {
    Scene s = base_scene();
    const dvec3 a1{0.9, 0.2, 0.4}, a2{0.1, 0.7, 0.95};
    // The front sphere leaves T = exp(-10) = 4.5e-5.
    s.spheres = {sphere({0, 0, 0}, 1.0, 5.0, a1), sphere({0, 0, -3}, 1.0, 0.5, a2)};
    const dvec3 ls = source(s, kDown);
    const dvec3 bg = s.lighting.background;
    const dvec3 front_only = a1 * ls * (1.0 - std::exp(-10.0));
    const dvec3 full = composite({{2.0, 5.0, a1}, {1.0, 0.0, dvec3(0.0)}, {2.0, 0.5, a2}}, ls, bg);
    ASSERT_GT(glm::length(full - front_only), 1e-6) << "the test needs a visible difference";

    s.render.min_transmittance = 1e-4;
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), front_only, 1e-14, "stopped");
    s.render.min_transmittance = 1e-5;  // below exp(-11), the transmittance behind both: no stop
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), full, 1e-13, "threshold not reached");
    s.render.min_transmittance = 0.0;
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), full, 1e-13, "never stops");

    // The stop also drops the background.
    s.spheres.pop_back();
    s.render.min_transmittance = 1e-4;
    expect_near3(reference_radiance(s, {0, 0, 5}, kDown), front_only, 1e-14, "no background after a stop");
}

// A cloud of spheres around the look-at point, with the hard cases mixed in: spheres containing the eye,
// behind it, sub-pixel ones, huge ones, exact duplicates (tied events), and boxes.
Scene random_scene(unsigned seed, int count, int width, int height, double fov) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Scene s = base_scene();
    s.render.min_transmittance = seed % 2 ? 1e-4 : 0.0;
    s.camera.position = {0.3, 1.0, 6.0};
    s.camera.look_at = {0.0, 0.5, 0.0};
    s.camera.fov_y_deg = fov;
    s.camera.width = width;
    s.camera.height = height;
    auto point = [&](double spread) { return dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * spread; };
    for (int k = 0; k < count; ++k) {
        Sphere sp;
        const double kind = u(rng);
        if (kind < 0.6) {
            sp = sphere(dvec3(0, 0.5, 0) + point(4.0), 0.05 + 0.4 * u(rng), 0.05 + 2.0 * u(rng), {u(rng), u(rng), u(rng)});
        } else if (kind < 0.8) {
            sp = sphere(dvec3(0, 0.5, 0) + point(6.0), 0.002 + 0.01 * u(rng), 5.0 * u(rng), {u(rng), u(rng), u(rng)});
        } else if (kind < 0.9) {
            sp = sphere(s.camera.position + point(14.0), 0.3 + 2.0 * u(rng), 0.01 * u(rng), {u(rng), u(rng), u(rng)});
        } else if (kind < 0.95) {
            sp = sphere(s.camera.position + point(1.0), 1.0 + u(rng), 0.01 * u(rng), {u(rng), u(rng), u(rng)});
        } else {
            sp = sphere(dvec3(0, 0.5, 0) + point(3.0), 0.2 + 0.3 * u(rng), 3.0 * u(rng), {u(rng), u(rng), u(rng)});
        }
        s.spheres.push_back(sp);
        if (u(rng) < 0.05) s.spheres.push_back(sp);  // identical events tie exactly
        if (u(rng) < 0.05) {
            sp.albedo = {u(rng), u(rng), u(rng)};  // same geometry, different medium: tied distances
            s.spheres.push_back(sp);
        }
    }
    s.boxes = {box({-3, -1.2, -3}, {3, -1, 3}, {0.2, 0.3, 0.1}), box({1.0, 0.0, -1.0}, {1.5, 2.5, -0.5}, {0.6, 0.1, 0.1})};
    return s;
}

TEST(Reference, RenderedPixelsAreTheOneRayRadiance) {
    const Scene s = random_scene(7, 300, 40, 30, 50.0);
    const Image img = render_reference(s);
    const CameraRays rays = make_camera_rays(s.camera);
    for (int j = 0; j < rays.height; ++j) {
        for (int i = 0; i < rays.width; ++i) {
            const dvec3 l = reference_radiance(s, rays.eye, rays.pixel_direction(i, j));
            for (int c = 0; c < 3; ++c) ASSERT_EQ(img.pixel(i, j)[c], float(l[c])) << i << "," << j << " ch " << c;
        }
    }
}

TEST(Reference, SphereOrderDoesNotChangeABit) {
    Scene s = random_scene(11, 400, 64, 48, 45.0);
    const Image before = render_reference(s);
    std::mt19937 rng(3);
    for (int round = 0; round < 3; ++round) {
        std::shuffle(s.spheres.begin(), s.spheres.end(), rng);
        const Image after = render_reference(s);
        EXPECT_TRUE(bit_identical(before, after)) << count_differing(before, after) << " channels differ";
    }
}

TEST(Reference, TiedEventsGiveTheSameBitsInAnyOrder) {
    // Coincident spheres tie at both ends; their sums must be accumulated in an order fixed by content.
    Scene s = base_scene();
    const double taus[5] = {0.1, 0.7, 1e-3, 0.7, 0.7};  // three equal: only scatter tells them apart
    const dvec3 albedos[5] = {{0.9, 0.1, 0.3}, {0.123456789, 0.987654321, 0.5555555}, {0.5, 0.5, 0.1},
                              {0.31415926, 0.2718281828, 0.1618033}, {0.7777777, 0.0123456, 0.4444444}};
    std::vector<int> order = {0, 1, 2, 3, 4};
    const std::vector<dvec3> origins = {{0, 0, 5}, {0.3, 0.2, 5}, {0, 0, 0.2}};
    std::vector<dvec3> first;
    int permutations = 0;
    do {
        s.spheres.clear();
        for (const int k : order) s.spheres.push_back(sphere({0, 0, 0}, 1.0, taus[k], albedos[k]));
        for (std::size_t r = 0; r < origins.size(); ++r) {
            const dvec3 l = reference_radiance(s, origins[r], kDown);
            if (first.size() <= r) first.push_back(l);
            EXPECT_EQ(std::memcmp(&l, &first[r], sizeof l), 0) << "permutation " << permutations << " ray " << r;
        }
        ++permutations;
    } while (std::next_permutation(order.begin(), order.end()));
    EXPECT_EQ(permutations, 120);
}

TEST(Reference, BinningKeepsSpheresGrazingTileCorners) {
    // The bins are cones around 16x16 tiles; a tile's corner pixel rays lie on its cone. A sphere just
    // outside the cone whose silhouette still takes in the corner pixel (by 1e-9 rad) must stay in the
    // tile's bin: an inexact bin drops it and the corner pixel shows the background. One sphere per scene,
    // so no other sphere can hide the corner.
    Scene s = base_scene();
    s.render.min_transmittance = 0.0;
    s.camera.position = {0.3, 1.0, 6.0};
    s.camera.look_at = {0.0, 0.5, 0.0};
    s.camera.fov_y_deg = 60.0;
    s.camera.width = 70;
    s.camera.height = 40;
    const CameraRays rays = make_camera_rays(s.camera);
    const double delta = 1e-9;
    int checked = 0;
    for (int j0 = 0; j0 < rays.height; j0 += 16) {
        for (int i0 = 0; i0 < rays.width; i0 += 16) {
            const int i1 = std::min(i0 + 16, rays.width), j1 = std::min(j0 + 16, rays.height);
            const dvec3 axis = rays.direction(0.5 * (i0 + i1), 0.5 * (j0 + j1));
            for (const int i : {i0, i1 - 1}) {
                for (const int j : {j0, j1 - 1}) {
                    const dvec3 dc = rays.pixel_direction(i, j);
                    const double beta = std::atan2(glm::length(glm::cross(axis, dc)), glm::dot(axis, dc));
                    const dvec3 away = glm::normalize(dc - glm::dot(dc, axis) * axis);
                    for (const double alpha : {0.002, 0.05}) {
                        const double dist = alpha < 0.01 ? 40.0 : 3.0;
                        const double phi = beta + alpha - delta;
                        const dvec3 u = std::cos(phi) * axis + std::sin(phi) * away;
                        const double chord = 2.0 * dist * std::sqrt(std::sin(2.0 * alpha) * delta);
                        s.spheres = {sphere(rays.eye + dist * u, dist * std::sin(alpha), 1.0 / chord, {0.9, 0.8, 0.7})};
                        const Image binned = render_reference(s, {.threads = 1});
                        const Image brute = render_reference(s, {.threads = 1, .brute_force = true});
                        ASSERT_TRUE(bit_identical(binned, brute))
                            << "corner " << i << "," << j << " alpha " << alpha << ": "
                            << count_differing(binned, brute) << " channels differ";
                        ASSERT_GT(std::abs(brute.pixel(i, j)[0] - float(s.lighting.background.x)), 0.1f)
                            << "corner " << i << "," << j << " must see the sphere";
                        ++checked;
                    }
                }
            }
        }
    }
    EXPECT_EQ(checked, 5 * 3 * 4 * 2);
}

TEST(Reference, BinnedMatchesBruteForceOnRandomScenes) {
    struct Case {
        unsigned seed;
        int width, height;
        double fov;
    };
    for (const Case& c : {Case{1, 96, 72, 45.0}, Case{2, 37, 23, 150.0}, Case{3, 128, 96, 20.0}, Case{4, 17, 100, 90.0}}) {
        const Scene s = random_scene(c.seed, 1000, c.width, c.height, c.fov);
        const Image binned = render_reference(s);
        const Image brute = render_reference(s, {.threads = 0, .brute_force = true});
        EXPECT_TRUE(bit_identical(binned, brute))
            << "seed " << c.seed << ": " << count_differing(binned, brute) << " channels differ";
        std::size_t background = 0;
        for (int j = 0; j < s.camera.height; ++j)
            for (int i = 0; i < s.camera.width; ++i)
                background += brute.pixel(i, j)[0] == float(s.lighting.background.x);
        EXPECT_LT(background, std::size_t(s.camera.width * s.camera.height) / 2) << "the scene must cover the view";
    }
}

TEST(Reference, ToleranceBinnedMatchesBruteForce) {
    const Scene s = random_scene(5, 300, 48, 40, 60.0);
    for (const double e : {1e-6, 3e-2}) {
        const Image binned = reference_tolerance(s, e);
        const Image brute = reference_tolerance(s, e, {.threads = 0, .brute_force = true});
        EXPECT_TRUE(bit_identical(binned, brute)) << "rel_error " << e << ": " << count_differing(binned, brute);
    }
}

TEST(Reference, ThreadCountDoesNotChangeABit) {
    const Scene s = random_scene(9, 500, 70, 50, 45.0);
    const Image one = render_reference(s, {.threads = 1});
    for (const int n : {2, 3, 8}) {
        const Image many = render_reference(s, {.threads = n});
        EXPECT_TRUE(bit_identical(one, many)) << n << " threads: " << count_differing(one, many) << " differ";
    }
    const Image tol_one = reference_tolerance(s, 1e-5, {.threads = 1});
    const Image tol_many = reference_tolerance(s, 1e-5, {.threads = 3});
    EXPECT_TRUE(bit_identical(tol_one, tol_many));
}

// The progress count (ReferenceOptions::pixels_done) ends at the frame's pixels, each counted once, with
// tiles cut by the image's edge, supersampling (pixels, not rays) and several threads; and counting
// changes no bit of the image.
TEST(Reference, ProgressCountsEveryPixelOnce) {
    Scene s = random_scene(4, 60, 37, 23, 45.0);
    s.camera.supersample = 2;
    const Image plain = render_reference(s, {.threads = 1});
    for (const int threads : {1, 3}) {
        std::atomic<std::uint64_t> done{5};  // added to, not reset
        const Image counted = render_reference(s, {.threads = threads, .pixels_done = &done});
        EXPECT_EQ(done.load(), 5u + 37u * 23u) << threads << " threads";
        EXPECT_TRUE(bit_identical(plain, counted)) << threads << " threads";
    }
}

TEST(Reference, ToleranceIsZeroInsideAndPositiveAtSilhouettes) {
    Scene s = base_scene();
    s.lighting.sun = dvec3(0.0);  // L_s constant over directions, so only geometry can change a pixel
    const dvec3 a{0.9, 0.6, 0.3};
    s.spheres = {sphere({0, 0, 0}, 1.0, 1e4, a)};  // opaque: the interior does not depend on the chord
    s.boxes = {box({1.6, -0.5, -1}, {2.4, 0.5, 0}, {0.8, 0.4, 0.2})};
    s.camera.position = {0, 0, 5};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_y_deg = 40;
    s.camera.width = 96;
    s.camera.height = 64;
    const double e = 0.02;  // with scale 5: a lateral move of about 0.1 + 0.1 at the sphere
    const Image tol = reference_tolerance(s, e);
    const CameraRays rays = make_camera_rays(s.camera);
    const dvec3 jump = glm::abs(a * s.lighting.ambient - s.lighting.background);

    int interior = 0, edge = 0, outside = 0;
    for (int j = 0; j < rays.height; ++j) {
        for (int i = 0; i < rays.width; ++i) {
            const dvec3 d = rays.pixel_direction(i, j);
            const dvec3 oc = rays.eye;  // sphere at the origin
            const double p = glm::length(oc - glm::dot(oc, d) * d);  // ray's distance from the centre
            const float* t = tol.pixel(i, j);
            const bool near_box = std::abs(rays.eye.x - d.x * rays.eye.z / d.z) > 1.2;
            if (p < 0.7) {
                ++interior;
                for (int c = 0; c < 3; ++c) ASSERT_LT(t[c], 1e-12) << "interior " << i << "," << j;
            } else if (std::abs(p - 1.0) < 0.1 && !near_box) {
                ++edge;
                for (int c = 0; c < 3; ++c) ASSERT_GT(t[c], 0.99 * jump[c]) << "silhouette " << i << "," << j;
            } else if (p > 1.3 && !near_box) {
                ++outside;
                for (int c = 0; c < 3; ++c) ASSERT_EQ(t[c], 0.0f) << "background " << i << "," << j;
            }
        }
    }
    EXPECT_GT(interior, 100);
    EXPECT_GT(edge, 20);
    EXPECT_GT(outside, 100);

    // The box face is flat: zero inside it, its edge shows the jump to the background.
    int face = 0, box_edge = 0;
    for (int j = 0; j < rays.height; ++j) {
        for (int i = 0; i < rays.width; ++i) {
            const dvec3 d = rays.pixel_direction(i, j);
            const double t_face = -rays.eye.z / d.z;  // where the ray meets the face plane z = 0
            const double x = rays.eye.x + t_face * d.x, y = rays.eye.y + t_face * d.y;
            const float* t = tol.pixel(i, j);
            if (x > 1.9 && x < 2.1 && std::abs(y) < 0.2) {
                ++face;
                for (int c = 0; c < 3; ++c) ASSERT_EQ(t[c], 0.0f) << "box face " << i << "," << j;
            } else if (x > 1.8 && x < 2.2 && std::abs(std::abs(y) - 0.5) < 0.05) {
                ++box_edge;
                const dvec3 box_jump = glm::abs(s.boxes[0].radiance - s.lighting.background);
                for (int c = 0; c < 3; ++c) ASSERT_GT(t[c], 0.99 * box_jump[c]) << "box edge " << i << "," << j;
            }
        }
    }
    EXPECT_GT(face, 4);
    EXPECT_GT(box_edge, 2);

    // Tolerance grows with the error it models.
    const Image small = reference_tolerance(s, 1e-7);
    double sum_small = 0, sum_large = 0;
    for (std::size_t k = 0; k < tol.rgb.size(); ++k) {
        sum_small += small.rgb[k];
        sum_large += tol.rgb[k];
    }
    EXPECT_LT(sum_small, 0.1 * sum_large);
}

TEST(Reference, RejectsEmptyCamera) {
    Scene s = base_scene();
    s.camera.width = 0;
    EXPECT_THROW(render_reference(s), std::invalid_argument);
    EXPECT_THROW(reference_tolerance(s, 1e-6), std::invalid_argument);
}

}  // namespace
}  // namespace brume
