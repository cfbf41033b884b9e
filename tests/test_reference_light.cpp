// The reference renderer's light extension (docs/accuracy.md, "Light through the smoke") against closed
// forms and against an independent quadrature written here: a sphere's shadow on a diffuse plane, a box's
// sharp shadow, emission, the sun integral along a ray through shadow cylinders, the per-sphere technique,
// and supersampling as the mean of its sub-rays.
#include "render/reference.h"
#include "render/ray_box.h"
#include "render/sun_light.h"

#include "test_scenes.h"

#include "sim/camera_rays.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;
using testing::sphere;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRel = 1e-9;  // closed forms hold to rounding; the quadrature is asked for 1e-10

double rayleigh(const Scene& s, const dvec3& d) {
    const double c = glm::dot(glm::normalize(s.lighting.sun_direction), d);
    return 3.0 / (16.0 * kPi) * (1.0 + c * c);
}

void expect_rel(const dvec3& got, const dvec3& want, double rel, const char* what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], rel * std::max(1.0, std::abs(want[c]))) << what << " channel " << c;
}

// A diffuse ground (top face y = 0) under a vertical sun, no background in view of the tests.
Scene ground_scene() {
    Scene s;
    s.lighting.ambient = {0.2, 0.3, 0.4};
    s.lighting.sun = {1.5, 1.2, 0.9};
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    s.lighting.shadows = true;
    s.render.min_transmittance = 0.0;
    Box ground{{-20, -1, -20}, {20, 0, 20}, {0.01, 0.02, 0.03}};
    ground.diffuse = {0.5, 0.6, 0.7};
    s.boxes.push_back(ground);
    return s;
}

// The radiance seen where a ray from high above lands on the ground at (x, 0, z).
dvec3 ground_radiance(const Scene& s, double x, double z, const ReferenceOptions& options = {}) {
    // Oblique, from far along +z: the view ray passes 3 or more units from every test object above y = 1.
    const dvec3 eye{x, 6.0, z + 12.0};
    return reference_radiance(s, eye, glm::normalize(dvec3(x, 0.0, z) - eye), options);
}

TEST(ReferenceLight, SphereShadowOnADiffusePlaneUnderAVerticalSun) {
    Scene s = ground_scene();
    const double r = 1.0, tau = 0.8;
    s.spheres.push_back(sphere({0.0, 2.0, 0.0}, r, tau));
    const Box& g = s.boxes[0];
    for (const double d : {0.0, 0.3, 0.7, 0.95, 0.999, 1.05, 2.5}) {
        const double t_sun = d < r ? std::exp(-2.0 * tau * std::sqrt(r * r - d * d)) : 1.0;
        const dvec3 want = g.radiance + g.diffuse * (s.lighting.ambient + s.lighting.sun * t_sun);
        // The same distance d from the axis along two directions.
        expect_rel(ground_radiance(s, d, 0.0), want, kRel, "along x");
        expect_rel(ground_radiance(s, d * 0.6, d * 0.8), want, kRel, "diagonal");
    }
    // Without shadows the sphere casts none.
    s.lighting.shadows = false;
    expect_rel(ground_radiance(s, 0.0, 0.0), g.radiance + g.diffuse * (s.lighting.ambient + s.lighting.sun), kRel,
               "shadows off");
}

TEST(ReferenceLight, BoxShadowIsSharpAndFollowsTheSun) {
    Scene s = ground_scene();
    s.boxes.push_back(Box{{-0.5, 1.0, -0.5}, {0.5, 1.5, 0.5}, {0.0, 0.0, 0.0}});
    const Box& g = s.boxes[0];
    const dvec3 dark = g.radiance + g.diffuse * s.lighting.ambient;
    const dvec3 lit = g.radiance + g.diffuse * (s.lighting.ambient + s.lighting.sun);
    expect_rel(ground_radiance(s, 0.0, 0.0), dark, kRel, "under the box");
    expect_rel(ground_radiance(s, 0.499, -0.499), dark, kRel, "just inside the shadow");
    expect_rel(ground_radiance(s, 0.501, 0.0), lit, kRel, "just outside");
    // A sun at 45 degrees travelling toward -x: the shadow of x in [-0.5, 0.5], y in [1, 1.5] lands on x in [-2, -0.5],
    // and the lit ground gets n.l = 1/sqrt(2).
    s.lighting.sun_direction = {-1.0, -1.0, 0.0};  // travelling toward -x
    const dvec3 lit45 = g.radiance + g.diffuse * (s.lighting.ambient + s.lighting.sun * std::sqrt(0.5));
    for (const double x : {-1.99, -1.2, -0.51}) expect_rel(ground_radiance(s, x, 0.0), dark, kRel, "in the shadow");
    for (const double x : {-2.01, -0.49, 0.0, 1.0}) expect_rel(ground_radiance(s, x, 0.0), lit45, kRel, "lit");
    expect_rel(ground_radiance(s, -1.2, 0.51), lit45, kRel, "beside the shadow");
}

// SunLight::box_blocks rejects a box by its light-space bounds before the exact ray test: on random
// boxes and suns, at points in front of, behind and beside each box and a rounding error from its
// shadow's edges, the answer is the exact test's over every box.
TEST(ReferenceLight, BoxBlocksIsTheExactTestOverEveryBox) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.05, 2.0);
    int blocked = 0, checked = 0;
    for (int scene = 0; scene < 40; ++scene) {
        Scene s;
        s.lighting.shadows = true;
        s.lighting.sun_direction = dvec3(unit(rng), -1.0 - std::abs(unit(rng)), unit(rng)) * (scene % 3 == 0 ? 0.3 : 1.0);
        if (scene % 5 == 0) s.lighting.sun_direction = {0.0, -1.0, 0.0};  // axis aligned: flat bounds
        for (int b = 0; b < 4; ++b) {
            const dvec3 lo(4.0 * unit(rng), 2.0 * unit(rng), 4.0 * unit(rng));
            s.boxes.push_back(Box{lo, lo + dvec3(size(rng), size(rng), size(rng)), dvec3(0.0)});
        }
        const SunLight sun(s);
        const dvec3 l = sun.toward_sun(), inv = inverse_direction(l);
        const auto exact = [&](const dvec3& x, int skip) {
            for (std::size_t k = 0; k < s.boxes.size(); ++k)
                if (int(k) != skip && ray_box_distance(s.boxes[k], x, l, inv) < std::numeric_limits<double>::infinity())
                    return true;
            return false;
        };
        for (int n = 0; n < 400; ++n) {
            const Box& b = s.boxes[std::size_t(n) % s.boxes.size()];
            // A point of the box (a corner, or within it), moved along the sun's ray either way, then a
            // little or a rounding error across it.
            const dvec3 corner((n & 1) ? b.max.x : b.min.x, (n & 2) ? b.max.y : b.min.y, (n & 4) ? b.max.z : b.min.z);
            const dvec3 inside = b.min + (b.max - b.min) * dvec3(0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng));
            const double nudge = (n % 3 == 0) ? 1e-13 : (n % 3 == 1) ? 1e-3 : 0.3;
            const dvec3 x = ((n & 8) ? corner : inside) - 3.0 * unit(rng) * l +
                            nudge * dvec3(unit(rng), unit(rng), unit(rng));
            const int skip = (n % 7 == 0) ? int(std::size_t(n) % s.boxes.size()) : -1;
            const bool want = exact(x, skip);
            ASSERT_EQ(sun.box_blocks(x, skip), want) << "scene " << scene << " point " << n;
            blocked += want;
            ++checked;
        }
    }
    EXPECT_GT(blocked, checked / 5);  // both answers were asked for
    EXPECT_GT(checked - blocked, checked / 5);
}

TEST(ReferenceLight, BoxShadowIntervalIsTheSweptBox) {
    const Box b{{-1, 2, -1}, {1, 3, 1}, {0, 0, 0}};
    const dvec3 up{0, 1, 0};
    double lo, hi;
    // A horizontal line under the box: in its shadow for x in [-1, 1].
    ASSERT_TRUE(box_shadow_interval(b, up, {-5, 0, 0}, {1, 0, 0}, lo, hi));
    EXPECT_DOUBLE_EQ(lo, 4.0);
    EXPECT_DOUBLE_EQ(hi, 6.0);
    // Above the box nothing is shadowed; beside it neither.
    EXPECT_FALSE(box_shadow_interval(b, up, {-5, 4, 0}, {1, 0, 0}, lo, hi));
    EXPECT_FALSE(box_shadow_interval(b, up, {-5, 0, 1.5}, {1, 0, 0}, lo, hi));
    // A vertical line through the box: shadowed from below up to the box's top face.
    ASSERT_TRUE(box_shadow_interval(b, up, {0, -1, 0}, {0, 1, 0}, lo, hi));
    EXPECT_TRUE(std::isinf(lo) && lo < 0.0);
    EXPECT_DOUBLE_EQ(hi, 4.0);
}

TEST(ReferenceLight, MediaInABoxShadowSeeOnlyTheAmbientLight) {
    Scene s = testing::small_scene(9, 9);
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    s.lighting.shadows = true;
    s.boxes.push_back(Box{{-5, 2, -5}, {5, 3, 5}, {0, 0, 0}});  // a roof over the sphere, out of view
    const Sphere sp = sphere({0.0, 0.0, 0.0}, 1.0, 1.3);
    s.spheres.push_back(sp);
    const dvec3 eye{0.0, 0.0, 5.0}, d{0.0, 0.0, -1.0};
    const double tr = std::exp(-2.0 * sp.extinction);
    expect_rel(reference_radiance(s, eye, d), sp.albedo * s.lighting.ambient * (1.0 - tr) + tr * s.lighting.background,
               kRel, "in the roof's shadow");
}

TEST(ReferenceLight, EmissionOnlySphereShowsEmissionTimesOpacity) {
    Scene s = testing::small_scene(9, 9);
    const dvec3 e{3.0, 1.5, 0.25};
    Sphere sp = sphere({0.0, 0.0, 0.0}, 1.0, 0.9, {0.0, 0.0, 0.0});
    sp.emission = e;
    s.spheres.push_back(sp);
    const dvec3 eye{0.0, 0.0, 5.0};
    for (const double h : {0.0, 0.5, 0.9}) {
        const dvec3 d = glm::normalize(dvec3(0.0, h, 0.0) - eye);
        const double p = glm::length(glm::cross(-eye, d));  // the ray's distance from the centre
        const double c = 2.0 * std::sqrt(1.0 - p * p);
        const double tr = std::exp(-sp.extinction * c);
        expect_rel(reference_radiance(s, eye, d), e * (1.0 - tr) + tr * s.lighting.background, kRel, "emission only");
    }
    // With scattering too the two source terms add: (albedo L_s + e)(1 - T).
    s.spheres[0].albedo = {0.5, 0.4, 0.3};
    const dvec3 d{0.0, 0.0, -1.0};
    const double tr = std::exp(-2.0 * sp.extinction);
    expect_rel(reference_radiance(s, eye, d),
               (s.spheres[0].albedo * testing::source_radiance(s, d) + e) * (1.0 - tr) + tr * s.lighting.background, kRel,
               "emission and scattering");
    // Two coincident spheres: sum tau_k e_k over sigma_t is the extinction-weighted mean emission.
    Sphere other = sp;
    other.albedo = dvec3(0.0);
    other.extinction = 0.3;
    other.emission = {0.0, 2.0, 8.0};
    Scene pair = testing::small_scene(9, 9);
    sp.albedo = dvec3(0.0);
    pair.spheres = {sp, other};
    const double sigma = sp.extinction + other.extinction;
    const double tp = std::exp(-2.0 * sigma);
    expect_rel(reference_radiance(pair, eye, d),
               (sp.extinction * sp.emission + other.extinction * other.emission) / sigma * (1.0 - tp) +
                   tp * pair.lighting.background,
               kRel, "coincident emitters");
}

// integral of f over [p, q] by Simpson's rule after t = p + (q - p)(1 - cos phi)/2, which removes the
// square-root behaviour at the ends; written independently of the renderer's quadrature.
double independent_integral(const std::function<double(double)>& f, double p, double q, int n = 20000) {
    const double h = kPi / n;
    double sum = 0.0;
    for (int k = 0; k <= n; ++k) {
        const double phi = k * h;
        const double t = p + (q - p) * 0.5 * (1.0 - std::cos(phi));
        const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
        sum += w * f(t) * (q - p) * 0.5 * std::sin(phi);
    }
    return sum * h / 3.0;
}

TEST(ReferenceLight, SunIntegralThroughSelfShadowAndAShadowCylinder) {
    // A horizontal ray at height y0 through a sphere lit from straight above, with a second sphere above
    // casting a shadow cylinder across part of the chord.
    Scene s = testing::small_scene(9, 9);
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    s.lighting.shadows = true;
    const Sphere receiver = sphere({0.0, 0.0, 0.0}, 1.0, 1.5, {0.8, 0.6, 0.4});
    const Sphere occluder = sphere({0.4, 3.0, 0.0}, 0.5, 2.0, {0.5, 0.5, 0.5});
    s.spheres = {receiver, occluder};
    const double y0 = 0.3;
    const dvec3 eye{-5.0, y0, 0.0}, d{1.0, 0.0, 0.0};
    const double a = std::sqrt(1.0 - y0 * y0);  // the chord is x in [-a, a]
    // T_sun at (x, y0, 0): the receiver above x, then the occluder's full chord where it is overhead.
    const auto t_sun = [&](double x) {
        double depth = receiver.extinction * (std::sqrt(1.0 - x * x) - y0);
        const double off = x - 0.4;
        if (std::abs(off) < 0.5) depth += occluder.extinction * 2.0 * std::sqrt(0.25 - off * off);
        return std::exp(-depth);
    };
    const double tau = receiver.extinction;
    const auto integrand = [&](double x) { return std::exp(-tau * (x + a)) * t_sun(x); };
    const double sun_part = independent_integral(integrand, -a, -0.1) + independent_integral(integrand, -0.1, 0.9) +
                            independent_integral(integrand, 0.9, a);
    const double tr = std::exp(-tau * 2.0 * a);
    const dvec3 scatter = tau * receiver.albedo;
    const dvec3 want = scatter * s.lighting.ambient * (1.0 - tr) / tau +
                       scatter * s.lighting.sun * rayleigh(s, d) * sun_part + tr * s.lighting.background;
    expect_rel(reference_radiance(s, eye, d), want, 1e-8, "exact shadows");

    // The per-sphere technique: T_sun at the receiver's centre, exp(-tau r), times the occluder's chord
    // 0.4 from its axis.
    ReferenceOptions per_sphere;
    per_sphere.shadows = ReferenceShadows::PerSphere;
    const double t_centre = std::exp(-tau * 1.0) * std::exp(-occluder.extinction * 2.0 * std::sqrt(0.25 - 0.16));
    const dvec3 want_per_sphere =
        receiver.albedo * (s.lighting.ambient + s.lighting.sun * rayleigh(s, d) * t_centre) * (1.0 - tr) +
        tr * s.lighting.background;
    expect_rel(reference_radiance(s, eye, d, per_sphere), want_per_sphere, kRel, "per-sphere shadows");
    EXPECT_NEAR(sun_transmittance_at_centres(s)[0], t_centre, 1e-15);
    EXPECT_DOUBLE_EQ(sun_transmittance_at_centres(s)[1], std::exp(-occluder.extinction * occluder.radius));
}

TEST(ReferenceLight, SunAlongTheViewRayHasNoKinks) {
    // Looking straight up the sun's path: every point of a chord sees the rest of its sphere and all of the
    // sphere above, so the sun integral has the closed form 2 r exp(-2 tau_B r) exp(-2 tau_A r).
    Scene s = testing::small_scene(9, 9);
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    s.lighting.shadows = true;
    const Sphere b = sphere({0.0, 0.0, 0.0}, 1.0, 0.7, {0.9, 0.5, 0.2});
    const Sphere a = sphere({0.0, 3.0, 0.0}, 1.0, 1.1, {0.3, 0.6, 0.9});
    s.spheres = {b, a};
    const dvec3 eye{0.0, -5.0, 0.0}, d{0.0, 1.0, 0.0};
    const double p = rayleigh(s, d);
    const double tb = std::exp(-2.0 * b.extinction), ta = std::exp(-2.0 * a.extinction);
    const dvec3 lb = b.albedo * s.lighting.ambient * (1.0 - tb) + b.extinction * b.albedo * s.lighting.sun * p * 2.0 * tb * ta;
    const dvec3 la = a.albedo * s.lighting.ambient * (1.0 - ta) + a.extinction * a.albedo * s.lighting.sun * p * 2.0 * ta;
    expect_rel(reference_radiance(s, eye, d), lb + tb * la + tb * ta * s.lighting.background, kRel, "along the sun");
}

TEST(ReferenceLight, SupersamplingIsTheMeanOfItsSubRays) {
    Scene s = testing::random_scene(12, 10, 8, 7, true);
    s.spheres[0].emission = {0.5, 1.0, 2.0};
    s.boxes[0].diffuse = {0.4, 0.5, 0.6};
    s.lighting.shadows = true;
    s.camera.supersample = 3;
    const Image img = render_reference(s);
    ASSERT_EQ(img.width, 12);
    ASSERT_EQ(img.height, 10);
    const CameraRays rays = make_camera_rays(s.camera);
    const int k = 3;
    for (int j = 0; j < img.height; ++j) {
        for (int i = 0; i < img.width; ++i) {
            dvec3 sum(0.0);
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a)
                    sum += reference_radiance(s, rays.eye, rays.direction(i + (a + 0.5) / k, j + (b + 0.5) / k));
            const dvec3 mean = sum / double(k * k);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(img.pixel(i, j)[c], mean[c], 1e-6 * std::max(1.0, mean[c])) << i << "," << j;
        }
    }
    // And supersampling changes the image: some pixels straddle an edge.
    Scene one = s;
    one.camera.supersample = 1;
    const Image single = render_reference(one);
    int differ = 0;
    for (std::size_t n = 0; n < img.rgb.size(); ++n) differ += std::abs(img.rgb[n] - single.rgb[n]) > 1e-4f;
    EXPECT_GT(differ, 0);
}

TEST(ReferenceLight, NewKeysAtTheirDefaultsChangeNotABit) {
    // A scene with no light keys against the same scene with each key set to its default explicitly
    // through the paths that read them (shadows off, supersample 1, zero emission and diffuse), and
    // against the per-sphere technique, which without shadows is the same model.
    const Scene s = testing::random_scene(40, 30, 30, 3, true);
    const Image plain = render_reference(s);
    ReferenceOptions per_sphere;
    per_sphere.shadows = ReferenceShadows::PerSphere;
    const Image other = render_reference(s, per_sphere);
    EXPECT_TRUE(std::equal(plain.rgb.begin(), plain.rgb.end(), other.rgb.begin()));
    // The image depends on the sun's shadows only when they are on.
    Scene lit = s;
    lit.lighting.shadows = true;
    const Image shadowed = render_reference(lit);
    EXPECT_FALSE(std::equal(plain.rgb.begin(), plain.rgb.end(), shadowed.rgb.begin()));
}

}  // namespace
}  // namespace brume
