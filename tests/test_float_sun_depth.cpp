// trace's lit-box optical depth toward the sun (render/float_sun_depth.h), summed in float eight spheres
// at a time on a grid of its own, against SunLight::optical_depth (the reference's double walk): within
// float rounding at random points under random clouds, whatever the sun's direction and however far the
// scene lies from the origin; 0 outside every shadow cylinder and above every sphere; spheres without
// medium add nothing. CPU only.
#include "render/float_sun_depth.h"
#include "render/sun_light.h"

#include "test_scenes.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>

namespace brume {
namespace {

// Radii from a twentieth to most of a unit, a few spheres without medium.
Scene random_cloud(int n, unsigned seed, const glm::dvec3& sun_direction, const glm::dvec3& offset) {
    return testing::random_sun_cloud(n, seed, sun_direction, 0.05, 0.9, offset, 17);
}

// At points below, inside and beside the cloud, the float sum is the double walk's to float rounding:
// each chord to a few float steps of the scene's size, summed over at most a few dozen spheres.
TEST(FloatSunDepth, TheDoubleWalksDepthToFloatRounding) {
    struct Case {
        glm::dvec3 sun, offset;
        int spheres;
    };
    for (const Case& c : {Case{{0.3, -1.0, 0.2}, {0.0, 0.0, 0.0}, 300}, Case{{-0.9, -0.25, 0.4}, {0.0, 0.0, 0.0}, 120},
                          Case{{0.0, -1.0, 0.0}, {0.0, 0.0, 0.0}, 60}, Case{{0.5, -0.6, -0.6}, {3000.0, -40.0, 1500.0}, 200},
                          Case{{1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 80}}) {
        const Scene s = random_cloud(c.spheres, unsigned(c.spheres), c.sun, c.offset);
        const SunLight sun(s);
        const FloatSunDepth fast(s, sun);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> pos(-3.0, 3.0);
        int under = 0;
        for (int n = 0; n < 4000; ++n) {
            const glm::dvec3 x = c.offset + glm::dvec3(pos(rng), pos(rng) * 0.7 + 0.5, pos(rng));
            const double want = sun.optical_depth(x), got = fast.optical_depth(x);
            const double scale = 1.0 + glm::length(c.offset) * 3e-4;  // float's step at the scene's place, in depth
            ASSERT_NEAR(got, want, 2e-5 * scale * std::max(1.0, want)) << "sun " << c.sun.x << " point " << n;
            under += want > 0.0;
        }
        EXPECT_GT(under, 1000);  // most points lay in some shadow: the test saw depths, not zeros
    }
}

// The walk in AVX2 and in any x86-64's instructions: the same operations, the same depths bit for bit.
TEST(FloatSunDepth, PortableInstructionsGiveTheSameDepths) {
    const Scene s = random_cloud(250, 5, {0.4, -1.0, -0.3}, glm::dvec3(0.0));
    const SunLight sun(s);
    const FloatSunDepth best(s, sun, MapInstructions::Best), portable(s, sun, MapInstructions::Portable);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(-3.0, 3.0);
    int nonzero = 0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 x(pos(rng), pos(rng) * 0.7 + 0.5, pos(rng));
        const double a = best.optical_depth(x), b = portable.optical_depth(x);
        ASSERT_EQ(a, b) << n;
        nonzero += a > 0.0;
    }
    EXPECT_GT(nonzero, 500);
}

TEST(FloatSunDepth, NothingOutsideTheShadowsAndAboveTheSpheres) {
    const Scene s = random_cloud(100, 3, {0.2, -1.0, 0.1}, glm::dvec3(0.0));
    const SunLight sun(s);
    const FloatSunDepth fast(s, sun);
    EXPECT_EQ(fast.optical_depth({40.0, 0.0, 0.0}), 0.0);   // beside every cylinder, outside the grid
    EXPECT_EQ(fast.optical_depth({0.0, 0.0, -40.0}), 0.0);
    EXPECT_EQ(fast.optical_depth(glm::dvec3(0.0, 1.0, 0.0) + 30.0 * sun.toward_sun()), 0.0);  // toward the sun
    Scene off = s;
    off.lighting.shadows = false;
    EXPECT_EQ(FloatSunDepth(off, SunLight(off)).optical_depth({0.0, 0.0, 0.0}), 0.0);
    Scene empty = s;
    empty.spheres.clear();
    EXPECT_EQ(FloatSunDepth(empty, SunLight(empty)).optical_depth({0.0, 0.0, 0.0}), 0.0);
}

// One sphere under a vertical sun, the closed form: below it, the whole chord 2 tau sqrt(r^2 - d^2).
TEST(FloatSunDepth, OneSphereClosedForm) {
    Scene s;
    s.lighting.shadows = true;
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    Sphere sp;
    sp.center = {1.0, 3.0, -2.0};
    sp.radius = 0.8;
    sp.extinction = 1.7;
    s.spheres.push_back(sp);
    const FloatSunDepth fast(s, SunLight(s));
    for (double d : {0.0, 0.3, 0.6, 0.79}) {
        const double want = 2.0 * 1.7 * std::sqrt(0.64 - d * d);
        EXPECT_NEAR(fast.optical_depth({1.0 + d, 0.0, -2.0}), want, 1e-5 * want) << d;
        EXPECT_NEAR(fast.optical_depth({1.0, 3.0, -2.0 + d}), 1.7 * std::sqrt(0.64 - d * d), 1e-5 * want) << d;  // half
    }
    EXPECT_EQ(fast.optical_depth({1.0 + 0.81, 0.0, -2.0}), 0.0);
}

// An atmosphere around a cloud (render/outsized_spheres.h): the grid's cells follow the puffs (half a
// puff across, where the atmosphere made them hundreds of units wide and every list held every puff),
// and the depths are still the double walk's, the atmosphere's chord included, inside the grid and far
// outside it.
TEST(FloatSunDepth, AnOutsizedSphereIsTakenWholeAndTheGridFollowsTheRest) {
    Scene s = random_cloud(200, 9, {0.3, -1.0, 0.2}, glm::dvec3(0.0));
    s.spheres.push_back(testing::sphere({40.0, -30.0, 20.0}, 1e4, 1e-4));
    const SunLight sun(s);
    const FloatSunDepth fast(s, sun);
    EXPECT_GT(fast.cell(), 0.0);
    EXPECT_LT(fast.cell(), 1.0);  // the puffs' mean diameter is about 0.95
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> near(-3.0, 3.0), far(-5000.0, 5000.0);
    for (int n = 0; n < 3000; ++n) {
        const glm::dvec3 x = n % 3 == 2 ? glm::dvec3(far(rng), far(rng) * 0.5, far(rng))
                                        : glm::dvec3(near(rng), near(rng) * 0.7 + 0.5, near(rng));
        const double want = sun.optical_depth(x), got = fast.optical_depth(x);
        ASSERT_GT(want, 0.0) << "point " << n;  // every point lies inside the atmosphere
        ASSERT_NEAR(got, want, 2e-5 * std::max(1.0, want)) << "point " << n;
    }
}

}  // namespace
}  // namespace brume
