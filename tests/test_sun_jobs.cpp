// The accurate shadow technique's pieces on a CPU (render/sun_jobs.h), apart from the walks that cut
// them (render/fast_tracer.cpp): a piece's closed form against the same integral in double, and its
// halving test; each piece resolved alone against the integral of the map's own depth by fine
// quadrature in double (so that what is measured is the pieces' linear depth and its halving, not the
// map's interpolation); a tile's interleaved jobs resolved into their pixels. CPU only; the images these
// pieces make are held to the exact reference by test_fast_tracer and test_gpu_light.
#include "render/sun_jobs.h"
#include "render/sun_light.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace brume {
namespace {

using sun_jobs::SunJobs;

// The integral over [0, len] of exp(-(attenuation + od_p) - (sigma_t + (od_q - od_p) / len) s) ds, in
// double: a piece's view attenuation from its segment's start, and its depth toward the sun linear
// from od_p to od_q.
double piece_integral_in_double(double od_p, double od_q, double len, double sigma_t, double attenuation) {
    const double x = (sigma_t + (od_q - od_p) / len) * len;
    const double phi = std::abs(x) < 1e-9 ? 1.0 - 0.5 * x : -std::expm1(-x) / x;
    return std::exp(-(attenuation + od_p)) * len * phi;
}

// Random pieces, eight at a time, as the walks make them: thin and thick media, the depth toward the
// sun rising or falling along the piece (a view ray leaving a shadow toward the sun), pieces from 1e-4
// to 2 units long.
TEST(SunJobs, APiecesClosedFormIsTheIntegralToFloatPrecision) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };
    double worst = 0.0;
    int halved = 0, kept = 0, checked = 0;
    for (int batch = 0; batch < 1000; ++batch) {
        alignas(32) float od_p[8], od_q[8], len[8], sigma_t[8], attenuation[8], weight[8];
        for (int l = 0; l < 8; ++l) {
            od_p[l] = float(unit(rng) < 0.2 ? 0.0 : 4.0 * unit(rng));
            od_q[l] = float(std::max(0.0, od_p[l] + (unit(rng) < 0.2 ? 0.0 : -6.0 + 12.0 * unit(rng))));
            len[l] = float(log_uniform(1e-4, 2.0));
            sigma_t[l] = float(unit(rng) < 0.1 ? 0.0 : log_uniform(1e-3, 30.0));
            attenuation[l] = float(unit(rng) < 0.3 ? 0.0 : 3.0 * unit(rng));
            weight[l] = float(0.05 + 0.95 * unit(rng));
        }
        simd::Int8 halve;
        const simd::Float8 got =
            sun_jobs::piece_integral8(simd::load8(od_p), simd::load8(od_q), simd::load8(len), simd::load8(sigma_t),
                                      simd::load8(attenuation), simd::load8(weight), halve);
        for (int l = 0; l < 8; ++l) {
            const double want = piece_integral_in_double(od_p[l], od_q[l], len[l], sigma_t[l], attenuation[l]);
            const double error = std::abs(double(got[l]) - want) / want;
            worst = std::max(worst, error);
            EXPECT_LE(error, 2e-5) << "od " << od_p[l] << " to " << od_q[l] << ", len " << len[l] << ", sigma_t "
                                   << sigma_t[l] << ", attenuation " << attenuation[l];
            // Halved where the light the piece may carry (its weight times the integrand at its start,
            // times the share of it its media scatter) times its change of depth exceeds the bound.
            const double share = std::min(1.0, double(sigma_t[l]) * len[l] / sun_jobs::kSunPieceThinDepth);
            const double carried = weight[l] * std::exp(-(double(attenuation[l]) + od_p[l])) * share *
                                   std::abs(double(od_q[l]) - od_p[l]);
            if (std::abs(carried - sun_jobs::kSunPieceDepthChange) < 1e-4) continue;  // float's rounding decides
            ++checked;
            const bool want_halve = carried > sun_jobs::kSunPieceDepthChange;
            EXPECT_EQ(halve[l] != 0, want_halve) << "carried " << carried;
            (want_halve ? halved : kept) += 1;
        }
    }
    std::printf("  8,000 pieces: worst relative error %.3g; %d to halve, %d kept of %d checked\n", worst, halved, kept,
                checked);
    EXPECT_GT(halved, 100);  // the draw reaches both sides of the test
    EXPECT_GT(kept, 100);
}

// One sphere of radius 1 at (0, 2, 0) under a vertical sun, with the eye at (-3, 0, 0): rays toward +x
// pass under it, through its shadow cylinder, where the depth toward the sun is 2 tau sqrt(1 - x^2) (a
// square-root edge at each side, where the linear depth of a piece is worst and the halving works).
Scene sphere_over_the_rays() {
    Scene s;
    s.lighting.shadows = true;
    s.lighting.sun_direction = {0.0, -1.0, 0.0};
    Sphere sp;
    sp.center = {0.0, 2.0, 0.0};
    sp.radius = 1.0;
    sp.extinction = 1.5;
    s.spheres.push_back(sp);
    // kMaxColumnSpheres more behind the eye (x < -3), whose shadows no ray's segment reaches: more than
    // kMaxColumnSpheres dense spheres, so that the map is a lattice whose spacing the one above sets (a
    // scene of a few takes each whole, and a cloud of a few hundred takes them through columns,
    // render/sun_depth_map.h).
    for (int k = 1; k <= SunDepthMap::kMaxColumnSpheres; ++k) {
        s.spheres.push_back(sp);
        s.spheres.back().center.x = -3.0 - 3.0 * k;
    }
    return s;
}

// A ray's lit pieces, handed to the jobs as the walks hand them (FastTracer::add_sun_job).
struct RayPieces {
    std::uint32_t ray = 0, pixel = 0;
    SunJobs::RayEnd end;

    void add(SunJobs& jobs, float p, float q, float a, float sigma_t, float transmittance, const simd::Float4& light) {
        jobs.add(jobs.rays[ray], ray, pixel, end, p, q, a, sigma_t, transmittance, light);
    }
};

// The integral over [p, q] of exp(-sigma_t (t - a) - depth(t)), depth the map's own along the ray, by
// Simpson's rule on steps of a thousandth of a cell (the map is piecewise smooth between its cells).
double integral_of_the_maps_depth(const SunDepthMap& map, const SunDepthMap::Ray& ray, double p, double q, double a,
                                  double sigma_t) {
    const int steps = 2 * int(std::ceil((q - p) / (0.001 * map.cell()) / 2.0));
    const double h = (q - p) / steps;
    double sum = 0.0;
    for (int i = 0; i <= steps; ++i) {
        const double t = p + i * h;
        const double f = std::exp(-sigma_t * (t - a) - double(map.optical_depth(ray, float(t))));
        sum += f * (i == 0 || i == steps ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0));
    }
    return sum * h / 3.0;
}

// Three rays' lit pieces along [0.5, 5.5], cut as the walks cut them (up to kSunPieceCells cells),
// two segments a ray, with the rays' segments taken in an order that interleaves them.
struct Segment {
    int ray;
    float a, b, sigma_t, transmittance;
};
constexpr Segment kSegments[] = {{0, 0.5f, 2.9f, 0.3f, 0.9f},
                                 {1, 0.5f, 3.1f, 1.2f, 1.0f},
                                 {0, 2.9f, 5.5f, 0.05f, 0.6f},
                                 {2, 0.5f, 5.5f, 0.7f, 0.8f},
                                 {1, 3.1f, 5.5f, 2.5f, 0.2f}};
const glm::dvec3 kDirections[3] = {glm::dvec3(1.0, 0.0, 0.0), glm::normalize(glm::dvec3(1.0, 0.0, 0.3)),
                                   glm::normalize(glm::dvec3(1.0, 0.4, -0.5))};
constexpr std::uint32_t kPixels[3] = {0, 9, 63};
const simd::Float4 kLight{0.0f, 0.5f, 0.25f, 0.125f};

// Calls f(segment, p, q) for each piece of each segment, in order.
template <class F>
void for_each_piece(float max_piece, F&& f) {
    for (const Segment& g : kSegments)
        for (float p = g.a; p < g.b;) {
            const float q = std::min(g.b, p + max_piece);
            f(g, p, q);
            p = q;
        }
}

// Each piece resolved alone: where its light times its change of depth stays within the bound, its
// closed form from the map's depths at its two ends; where it does not, halved, and then much nearer
// the integral of the map's own depth than that closed form (the square-root edges of the shadow,
// where a linear depth over a whole piece is worst).
TEST(SunJobs, APieceIsItsClosedFormOrHalvedNearerTheIntegral) {
    const Scene s = sphere_over_the_rays();
    const glm::dvec3 eye(-3.0, 0.0, 0.0);
    const SunDepthMap map(s, SunLight(s), eye, 1);
    ASSERT_FALSE(map.empty());
    int halved = 0, kept = 0;
    for_each_piece(sun_jobs::kSunPieceCells * map.cell(), [&](const Segment& g, float p, float q) {
        SunJobs jobs;
        jobs.clear();
        jobs.rays.push_back(map.ray(kDirections[g.ray]));
        RayPieces ray;
        ray.add(jobs, p, q, g.a, g.sigma_t, g.transmittance, kLight);
        std::vector<glm::dvec3> sums(64, glm::dvec3(0.0));
        sun_jobs::resolve(map, jobs, sums.data(), simd::GatherByLanes{});
        const double got = sums[0].x / 0.5;  // kLight's first channel

        const SunDepthMap::Ray& m = jobs.rays[0];
        const double od_p = map.optical_depth(m, p), od_q = map.optical_depth(m, q);
        const double attenuation = double(g.sigma_t) * (p - g.a);
        const double closed_form = piece_integral_in_double(od_p, od_q, q - p, g.sigma_t, attenuation);
        const double integral = integral_of_the_maps_depth(map, m, p, q, g.a, g.sigma_t);
        const double carried = g.transmittance * std::exp(-(attenuation + od_p)) *
                               std::min(1.0, double(g.sigma_t) * (q - p) / sun_jobs::kSunPieceThinDepth) *
                               std::abs(od_q - od_p);
        if (std::abs(carried - sun_jobs::kSunPieceDepthChange) < 1e-3) return;  // float's rounding decides
        if (carried < sun_jobs::kSunPieceDepthChange) {
            ++kept;
            EXPECT_NEAR(got, closed_form, 1e-5 * closed_form) << "ray " << g.ray << " [" << p << ", " << q << "]";
        } else {
            ++halved;
            std::printf("  ray %d [%.2f, %.2f], depth %.3f to %.3f: the integral %.6f, halved %.6f, its closed form "
                        "%.6f\n",
                        g.ray, p, q, od_p, od_q, integral, got, closed_form);
            EXPECT_LT(std::abs(got - integral), 0.2 * std::abs(closed_form - integral))
                << "ray " << g.ray << " [" << p << ", " << q << "]";
        }
    });
    EXPECT_GE(halved, 2);  // the pieces across the shadow's edges on rays 0 and 1
    EXPECT_GT(kept, 20);
}

// The same pieces as one tile's jobs, the rays' pieces interleaved and sharing their points: each
// pixel's sum is the sum of its pieces resolved alone, each channel its light's, and no other pixel
// has any.
TEST(SunJobs, ATilesJobsResolveIntoTheirPixels) {
    const Scene s = sphere_over_the_rays();
    const glm::dvec3 eye(-3.0, 0.0, 0.0);
    const SunDepthMap map(s, SunLight(s), eye, 1);
    ASSERT_FALSE(map.empty());
    const float max_piece = sun_jobs::kSunPieceCells * map.cell();

    SunJobs tile;
    tile.clear();
    RayPieces rays[3];
    for (int r = 0; r < 3; ++r) {
        tile.rays.push_back(map.ray(kDirections[r]));
        rays[r].ray = std::uint32_t(r);
        rays[r].pixel = kPixels[r];
    }
    std::vector<double> alone(64, 0.0);
    for_each_piece(max_piece, [&](const Segment& g, float p, float q) {
        rays[g.ray].add(tile, p, q, g.a, g.sigma_t, g.transmittance, kLight);
        SunJobs one;
        one.clear();
        one.rays.push_back(tile.rays[std::size_t(g.ray)]);
        RayPieces ray;
        ray.add(one, p, q, g.a, g.sigma_t, g.transmittance, kLight);
        std::vector<glm::dvec3> sums(64, glm::dvec3(0.0));
        sun_jobs::resolve(map, one, sums.data(), simd::GatherByLanes{});
        alone[kPixels[g.ray]] += sums[0].x;
    });
    EXPECT_LT(tile.points, 2 * tile.count);  // pieces shared their points, across the interleaving too

    std::vector<glm::dvec3> sums(64, glm::dvec3(0.0));
    sun_jobs::resolve(map, tile, sums.data(), simd::GatherByLanes{});
    for (std::uint32_t pixel = 0; pixel < 64; ++pixel) {
        if (alone[pixel] == 0.0) {
            EXPECT_EQ(sums[pixel], glm::dvec3(0.0)) << "pixel " << pixel << " has no job";
            continue;
        }
        EXPECT_NEAR(sums[pixel].x, alone[pixel], 1e-6 * alone[pixel]) << "pixel " << pixel;
        EXPECT_NEAR(sums[pixel].y, 0.5 * sums[pixel].x, 1e-6 * sums[pixel].x) << "pixel " << pixel;
        EXPECT_NEAR(sums[pixel].z, 0.25 * sums[pixel].x, 1e-6 * sums[pixel].x) << "pixel " << pixel;
    }
}

}  // namespace
}  // namespace brume
