// The light-space optical-depth map of trace's accurate shadow technique (render/sun_depth_map.h):
// exact at its vertices (against render/sun_light.h's optical_depth, the reference's own), 0 outside
// every shadow cylinder, the whole column's depth below the lowest sphere, converging as the lattice
// is refined, the same for any thread count, the same when built again in place, and within its memory
// budget. CPU only.
#include "render/sun_depth_map.h"
#include "render/sun_light.h"

#include "test_scenes.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <random>
#include <stdexcept>
#include <string>

namespace brume {
namespace {

Scene random_cloud(int n, unsigned seed, const glm::dvec3& sun_direction) {
    return testing::random_sun_cloud(n, seed, sun_direction);
}
// More dense spheres than the map takes through columns (kMaxColumnSpheres): a lattice.
constexpr int kLatticeSpheres = SunDepthMap::kMaxColumnSpheres + 24;

// Points along random rays from an origin, the way the tracer asks: origin + t d.
struct Probe {
    glm::dvec3 d;
    double t;
};
std::vector<Probe> probes(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> t(5.0, 11.0);  // through the cloud, from the eyes below
    std::vector<Probe> out;
    for (int k = 0; k < n; ++k) out.push_back({glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))), t(rng)});
    return out;
}

// The probes' points in a map's lattice coordinates, as the tracer hands them to optical_depths.
struct LatticePoints {
    std::vector<float> gu, gv, gs;
};
LatticePoints lattice_points(const SunDepthMap& map, const std::vector<Probe>& ps) {
    LatticePoints out;
    for (const Probe& p : ps) {
        const SunDepthMap::Ray r = map.ray(p.d);
        out.gu.push_back(r.u0 + float(p.t) * r.du);
        out.gv.push_back(r.v0 + float(p.t) * r.dv);
        out.gs.push_back(r.s0 + float(p.t) * r.ds);
    }
    return out;
}

TEST(SunDepthMap, EmptyWithoutShadowsOrSpheres) {
    Scene s = random_cloud(10, 1, {0.3, -1.0, 0.2});
    s.lighting.shadows = false;
    EXPECT_TRUE(SunDepthMap(s, SunLight(s), glm::dvec3(0.0), 1).empty());
    Scene none = random_cloud(0, 1, {0.3, -1.0, 0.2});
    EXPECT_TRUE(SunDepthMap(none, SunLight(none), glm::dvec3(0.0), 1).empty());
}

// A shadowed scene of one sphere of radius 1 at (0, 2, 0).
Scene one_sphere(const glm::dvec3& sun_direction, double extinction) {
    Scene s;
    s.lighting.shadows = true;
    s.lighting.sun_direction = sun_direction;
    Sphere sp;
    sp.center = {0.0, 2.0, 0.0};
    sp.radius = 1.0;
    sp.extinction = extinction;
    s.spheres.push_back(sp);
    return s;
}

// A single sphere under a vertical sun: along the vertical through its centre, the depth is the part of
// the chord above the point: 2 r tau below the sphere, tau (r + c - y) inside, 0 above. Vertices lie
// exactly on that axis only by chance, but the column through the centre is linear in s between the
// chord's ends, so the interpolation is exact there up to the lateral neighbours; compare loosely, and
// exactly far outside.
TEST(SunDepthMap, OneSphereUnderAVerticalSun) {
    const Scene s = one_sphere({0.0, -1.0, 0.0}, 1.5);
    const glm::dvec3 eye(0.0, 0.0, -5.0);
    const SunLight sun(s);
    const SunDepthMap map(s, sun, eye, 1);
    ASSERT_FALSE(map.empty());
    const auto depth_at = [&](const glm::dvec3& x) {
        const glm::dvec3 rel = x - eye;
        const double t = glm::length(rel);
        return double(map.optical_depth(map.ray(rel / t), float(t)));
    };
    EXPECT_NEAR(depth_at({0.0, -1.0, 0.0}), 3.0, 0.02);   // below: the whole chord
    EXPECT_NEAR(depth_at({0.0, 2.0, 0.0}), 1.5, 0.02);    // the centre: half of it
    EXPECT_EQ(depth_at({0.0, 3.5, 0.0}), 0.0);            // above the sphere
    EXPECT_EQ(depth_at({3.0, 0.0, 0.0}), 0.0);            // beside its shadow
    EXPECT_EQ(depth_at({0.0, -1.0, 40.0}), 0.0);          // far outside the lattice
}

// The spacing is 0.09 of the mean radius where a sphere's depth across, tau r, is 1 or more, and
// 0.09 / (tau r)^2 radii in thinner media, up to twice as wide (render/sun_depth_map.cpp
// thin_media_widening): the same single sphere at five densities.
TEST(SunDepthMap, ThinMediaWidenTheSpacingAsTheirDepthAcrossFalls) {
    // kMaxColumnSpheres + 1 spheres in rows: a lattice (a scene of at most kMaxWholeSpheres takes every
    // sphere whole, and a dense one of at most kMaxColumnSpheres takes them through columns).
    Scene s = one_sphere({0.2, -1.0, 0.1}, 1.0);
    const Sphere sp = s.spheres[0];
    for (int k = 1; k <= SunDepthMap::kMaxColumnSpheres; ++k) {  // one behind another along the sun's rays
        s.spheres.push_back(sp);
        s.spheres.back().center -= 2.1 * k * glm::normalize(s.lighting.sun_direction);
    }
    const auto spacing = [&](double tau_r) {
        for (Sphere& each : s.spheres) each.extinction = tau_r / sp.radius;
        return double(SunDepthMap(s, SunLight(s), glm::dvec3(0.0, 0.0, -5.0), 1).cell());
    };
    const double dense = 0.09 * sp.radius;
    EXPECT_NEAR(spacing(4.0), dense, 1e-6);
    EXPECT_NEAR(spacing(1.0), dense, 1e-6);
    EXPECT_NEAR(spacing(0.8), dense / 0.64, 1e-6);  // 1 / (tau r)^2
    EXPECT_NEAR(spacing(0.5), 2.0 * dense, 1e-6);   // at most twice
    EXPECT_NEAR(spacing(0.01), 2.0 * dense, 1e-6);
    // The 99th percentile of the spheres' depths across: one thin sphere among dense ones keeps the
    // dense spacing.
    s.spheres.resize(1);
    s.spheres[0].extinction = 3.0;
    for (int k = 1; k <= SunDepthMap::kMaxColumnSpheres; ++k) {
        Sphere other = sp;
        other.center.x = 0.02 * k;
        other.extinction = 3.0;
        s.spheres.push_back(other);
    }
    s.spheres[7].extinction = 0.01;
    EXPECT_NEAR(double(SunDepthMap(s, SunLight(s), glm::dvec3(0.0, 0.0, -5.0), 1).cell()), dense, 1e-6);
}

// A scene of at most kMaxWholeSpheres spheres takes each one whole: every lookup is its closed form, so
// the map is exact anywhere to float rounding (a lattice blurs a lone sphere's shadow edge), its
// lattice the least one, and its spacing, which sets the pieces along the view rays, kCellPerRadius
// (0.09) of the spheres' lower median radius over kWholeSpheresFiner (8). Past kMaxWholeSpheres (48)
// spheres, the lattice holds them all.
TEST(SunDepthMap, AFewSpheresAreTakenWholeAndExactEverywhere) {
    Scene s = one_sphere({0.3, -1.0, 0.2}, 1.2);
    for (const double radius : {0.5, 2.0, 0.7}) {
        Sphere sp = s.spheres[0];
        sp.radius = radius;
        sp.center += glm::dvec3(1.1 * radius, 0.9 - radius, 0.4 * radius);  // overlapping shadows
        sp.extinction = 2.5 / radius;
        s.spheres.push_back(sp);
    }
    const glm::dvec3 eye(0.3, 1.0, -6.0);
    const SunLight sun(s);
    const SunDepthMap map(s, sun, eye, 1);
    ASSERT_FALSE(map.empty());
    EXPECT_EQ(map.outsized().size(), 4u);
    EXPECT_EQ(map.size_u() * map.size_v() * map.size_s(), 18);
    EXPECT_NEAR(double(map.cell()), 0.09 * 0.7 / 8.0, 1e-9);  // radii 0.5, 0.7, 1, 2: the lower median 0.7
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> within(-3.0, 3.0);
    double worst = 0.0, deepest = 0.0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 x = glm::dvec3(0.0, 2.0, 0.0) + glm::dvec3(within(rng), within(rng), within(rng));
        const glm::dvec3 rel = x - eye;
        const double t = glm::length(rel);
        const double want = sun.optical_depth(x);
        worst = std::max(worst, std::abs(double(map.optical_depth(map.ray(rel / t), float(t))) - want));
        deepest = std::max(deepest, want);
    }
    EXPECT_GT(deepest, 5.0);  // the probes reach the shadows
    EXPECT_LT(worst, 1e-3 * deepest) << "worst error, deepest " << deepest;
    EXPECT_FALSE(map.has_columns());
    EXPECT_TRUE(SunDepthMap::takes_spheres_exactly(s));
    // Past kMaxWholeSpheres these dense spheres (tau r 1.2-2.5) go to the columns (none of them
    // outsized, none whole, the lattice still the least one), and past kMaxColumnSpheres to a lattice.
    for (int k = 1; k <= SunDepthMap::kMaxWholeSpheres - 3; ++k) {
        s.spheres.push_back(s.spheres[0]);
        s.spheres.back().center.x -= 2.5 * k;
    }
    const SunDepthMap columns(s, SunLight(s), eye, 1);
    EXPECT_TRUE(columns.outsized().empty());
    EXPECT_TRUE(columns.has_columns());
    EXPECT_EQ(columns.size_u() * columns.size_v() * columns.size_s(), 18);
    EXPECT_TRUE(SunDepthMap::takes_spheres_exactly(s));
    for (int k = 0; k < SunDepthMap::kMaxColumnSpheres - SunDepthMap::kMaxWholeSpheres; ++k) {
        s.spheres.push_back(s.spheres[0]);
        s.spheres.back().center.z -= 2.5 * (k + 1);
    }
    ASSERT_EQ(s.spheres.size(), std::size_t(SunDepthMap::kMaxColumnSpheres) + 1);
    const SunDepthMap lattice(s, SunLight(s), eye, 1);
    EXPECT_TRUE(lattice.outsized().empty());
    EXPECT_FALSE(lattice.has_columns());
    EXPECT_GT(lattice.size_u() * lattice.size_v() * lattice.size_s(), 1000);
    EXPECT_FALSE(SunDepthMap::takes_spheres_exactly(s));
}

// A scene taken whole reads each point's closed forms eight at a time (optical_depths, the tracer's
// lanes) as one at a time, bit for bit: the lanes skip a sphere whose shadow none of their points is in
// (SunDepthMap::outsized_depth8), which must add exactly what it would have, 0. Batches mix points in
// and out of each shadow, and some batches are in none.
TEST(SunDepthMap, WholeSpheresReadTheSameEightAtATimeAsOneAtATime) {
    const Scene s = random_cloud(40, 12, {0.3, -1.0, 0.4});
    ASSERT_LE(s.spheres.size(), std::size_t(SunDepthMap::kMaxWholeSpheres));
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const SunDepthMap map(s, SunLight(s), eye, 1);
    ASSERT_EQ(map.outsized().size(), s.spheres.size());
    const std::vector<Probe> ps = probes(4000, 9);
    const LatticePoints g = lattice_points(map, ps);
    std::vector<float> batch(ps.size());
    map.optical_depths(g.gu.data(), g.gv.data(), g.gs.data(), batch.data(), ps.size(), simd::GatherByLanes{});
    int mixed = 0, clear = 0;  // batches with some points in a shadow and some in none; with all in none
    for (std::size_t first = 0; first < ps.size(); first += 8) {
        int lit = 0;  // points in no shadow
        for (std::size_t k = first; k < first + 8; ++k) {
            const float one = map.optical_depth(map.ray(ps[k].d), float(ps[k].t));
            EXPECT_EQ(std::bit_cast<std::uint32_t>(batch[k]), std::bit_cast<std::uint32_t>(one)) << k << ": " << batch[k] << " against " << one;
            lit += one == 0.0f ? 1 : 0;
        }
        mixed += lit > 0 && lit < 8 ? 1 : 0;
        clear += lit == 8 ? 1 : 0;
    }
    std::printf("  %d batches of eight mixed, %d in no shadow, of %zu\n", mixed, clear, ps.size() / 8);
    EXPECT_GT(mixed, 20);
    EXPECT_GT(clear, 20);
}

// A cloud of dense spheres, more than kMaxWholeSpheres and at most kMaxColumnSpheres, is taken through
// light-space columns: every lookup walks its column's spheres from the sun down and adds each chord in
// closed form, so the map is exact anywhere to float rounding, as where every sphere is whole; with an
// outsized fog sphere around it (in no column, a lookup adds its chord), too. Eight at a time (the
// tracer's lanes) it reads what it reads one at a time, bit for bit, whether the eight points share a
// column (along one ray) or not (scattered).
TEST(SunDepthMap, ASparseCloudIsTakenExactlyThroughColumns) {
    const Scene cloud = random_cloud(120, 17, {0.3, -1.0, 0.4});
    Scene fogged = cloud;
    fogged.spheres.push_back(testing::sphere({3.0, -20.0, 7.0}, 1e4, 1e-4));
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    for (const Scene* s : std::initializer_list<const Scene*>{&cloud, &fogged}) {
        const SunLight sun(*s);
        const SunDepthMap map(*s, sun, eye, 1);
        ASSERT_TRUE(map.has_columns());
        EXPECT_TRUE(SunDepthMap::takes_spheres_exactly(*s));
        EXPECT_EQ(map.outsized().size(), s == &fogged ? 1u : 0u);
        EXPECT_EQ(map.size_u() * map.size_v() * map.size_s(), 18);
        // Scattered points, and runs of eight along a ray through the cloud.
        std::vector<Probe> ps = probes(4000, 19);
        for (const Probe& p : probes(200, 23))
            for (int k = 0; k < 8; ++k) ps.push_back({p.d, p.t + 0.01 * k});
        double worst = 0.0, deepest = 0.0;
        for (const Probe& p : ps) {
            const double want = sun.optical_depth(eye + p.t * p.d);
            worst = std::max(worst, std::abs(double(map.optical_depth(map.ray(p.d), float(p.t))) - want));
            deepest = std::max(deepest, want);
        }
        std::printf("  %s: worst %.3g of a deepest %.3g\n", s == &fogged ? "in a fog" : "alone", worst, deepest);
        EXPECT_GT(deepest, 5.0);  // the probes reach the shadows
        EXPECT_LT(worst, 1e-4 * deepest) << "worst error, deepest " << deepest;
        const LatticePoints g = lattice_points(map, ps);
        std::vector<float> batch(ps.size() + 8);
        map.optical_depths(g.gu.data(), g.gv.data(), g.gs.data(), batch.data(), ps.size() / 8 * 8, simd::GatherByLanes{});
        for (std::size_t k = 0; k < ps.size() / 8 * 8; ++k) {
            const float one = map.optical_depth(map.ray(ps[k].d), float(ps[k].t));
            ASSERT_EQ(std::bit_cast<std::uint32_t>(batch[k]), std::bit_cast<std::uint32_t>(one)) << k << ": " << batch[k] << " against " << one;
        }
    }
}

// Which spheres go where: up to kMaxWholeSpheres each whole; past it, a cloud of dense spheres (the
// 99th percentile of tau r at least 1) of at most kMaxColumnSpheres through columns, and a lattice past
// that; thin smoke (where the lattice widens its spacing) a lattice. takes_spheres_exactly says the
// same from the scene alone.
TEST(SunDepthMap, DenseCloudsOfAFewHundredSpheresTakeColumnsAndThinOnesALattice) {
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const auto layout = [&](const Scene& s) {
        const SunDepthMap map(s, SunLight(s), eye, 1);
        const bool whole = !map.outsized().empty() && map.outsized().size() == s.spheres.size();
        EXPECT_EQ(SunDepthMap::takes_spheres_exactly(s), whole || map.has_columns()) << s.spheres.size();
        return whole ? "whole" : map.has_columns() ? "columns" : "lattice";
    };
    const auto thinned = [](Scene s, double depth_across) {
        for (Sphere& sp : s.spheres) sp.extinction = std::min(sp.extinction, depth_across / sp.radius);
        return s;
    };
    const Scene few = random_cloud(SunDepthMap::kMaxWholeSpheres, 3, {0.3, -1.0, 0.4});
    const Scene some = random_cloud(SunDepthMap::kMaxWholeSpheres + 1, 3, {0.3, -1.0, 0.4});
    const Scene most = random_cloud(SunDepthMap::kMaxColumnSpheres, 3, {0.3, -1.0, 0.4});
    const Scene many = random_cloud(SunDepthMap::kMaxColumnSpheres + 1, 3, {0.3, -1.0, 0.4});
    EXPECT_STREQ(layout(few), "whole");
    EXPECT_STREQ(layout(some), "columns");
    EXPECT_STREQ(layout(most), "columns");
    EXPECT_STREQ(layout(many), "lattice");
    EXPECT_STREQ(layout(thinned(some, 0.9)), "lattice");  // tau r at most 0.9: the lattice widens
    EXPECT_STREQ(layout(thinned(most, 1.05)), "columns");  // at most 1.05 (and that at the 99th percentile)
    EXPECT_STREQ(layout(thinned(few, 0.1)), "whole");
}

// BRUME_SUN_COLUMNS overrides the rule, for timing the columns against the lattice on the same frames:
// always takes a lattice cloud's spheres through columns (exactly: the lookups are the reference's to
// float rounding), never puts a columns cloud's in a lattice, auto (or unset) is the rule, and any
// other value is refused by name. A scene of at most kMaxWholeSpheres is whole whatever it says.
TEST(SunDepthMap, BrumeSunColumnsOverridesTheRule) {
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const Scene lattice = random_cloud(kLatticeSpheres, 71, {0.3, -1.0, 0.4});
    const Scene columns = random_cloud(120, 72, {0.3, -1.0, 0.4});
    const Scene whole = random_cloud(SunDepthMap::kMaxWholeSpheres, 73, {0.3, -1.0, 0.4});
    const auto has_columns = [&](const Scene& s) {
        const bool built = SunDepthMap(s, SunLight(s), eye, 1).has_columns();
        EXPECT_EQ(SunDepthMap::takes_spheres_exactly(s), built || s.spheres.size() <= std::size_t(SunDepthMap::kMaxWholeSpheres));
        return built;
    };
    ::setenv("BRUME_SUN_COLUMNS", "always", 1);
    EXPECT_TRUE(has_columns(lattice));
    EXPECT_TRUE(has_columns(columns));
    EXPECT_FALSE(has_columns(whole));
    const SunLight sun(lattice);
    const SunDepthMap exact(lattice, sun, eye, 1);
    double worst = 0.0, deepest = 0.0;
    for (const Probe& p : probes(2000, 74)) {
        const double want = sun.optical_depth(eye + p.t * p.d);
        worst = std::max(worst, std::abs(double(exact.optical_depth(exact.ray(p.d), float(p.t))) - want));
        deepest = std::max(deepest, want);
    }
    EXPECT_LT(worst, 1e-4 * deepest) << "deepest " << deepest;
    ::setenv("BRUME_SUN_COLUMNS", "never", 1);
    EXPECT_FALSE(has_columns(lattice));
    EXPECT_FALSE(has_columns(columns));
    ::setenv("BRUME_SUN_COLUMNS", "auto", 1);
    EXPECT_FALSE(has_columns(lattice));
    EXPECT_TRUE(has_columns(columns));
    ::setenv("BRUME_SUN_COLUMNS", "sometimes", 1);
    try {
        (void)SunDepthMap(columns, SunLight(columns), eye, 1);
        ADD_FAILURE() << "BRUME_SUN_COLUMNS=sometimes was taken";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("BRUME_SUN_COLUMNS='sometimes'"), std::string::npos) << e.what();
    }
    ::unsetenv("BRUME_SUN_COLUMNS");
    EXPECT_TRUE(has_columns(columns));
}

// A budget below the least lattice a finite spacing gives (4 x 4 x 2) gets that lattice: under 18 the
// spacing search had no end, and at 18-31 it ended at an infinite spacing whose lookups read no shadow.
TEST(SunDepthMap, ABudgetBelowTheLeastLatticeGetsIt) {
    const Scene s = random_cloud(kLatticeSpheres, 4, {0.2, -1.0, 0.3});
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const SunLight sun(s);
    for (const std::size_t budget : {std::size_t(5), std::size_t(20)}) {
        const SunDepthMap map(s, sun, eye, 1, budget);
        ASSERT_FALSE(map.empty());
        EXPECT_EQ(map.size_u() * map.size_v() * map.size_s(), 32) << budget;
        EXPECT_TRUE(std::isfinite(map.cell())) << budget;
        // A lookup reads a number (at an infinite spacing the ray's coordinates were NaN). Its vertices
        // lie at the cloud's edges, so it is blurred to nothing: a budget this small buys no shadow.
        const glm::dvec3 below = s.spheres[0].center - 3.0 * sun.toward_sun(), rel = below - eye;
        const SunDepthMap::Ray ray = map.ray(rel / glm::length(rel));
        EXPECT_TRUE(std::isfinite(ray.u0) && std::isfinite(ray.du) && std::isfinite(ray.s0)) << budget;
        const double got = map.optical_depth(ray, float(glm::length(rel)));
        EXPECT_TRUE(std::isfinite(got) && got >= 0.0) << budget << ": " << got;
    }
}

// Every vertex holds the exact optical depth of its point: probing at vertices (through the same ray
// arithmetic the tracer uses) matches SunLight::optical_depth to float rounding.
TEST(SunDepthMap, ExactAtItsVertices) {
    const Scene s = random_cloud(kLatticeSpheres, 7, {0.4, -1.0, 0.3});
    const glm::dvec3 eye(0.5, 1.0, -9.0);
    const SunLight sun(s);
    const SunDepthMap map(s, sun, eye, 2);
    ASSERT_FALSE(map.empty());
    const glm::dvec3 u = sun.grid_u(), v = sun.grid_v(), l = sun.toward_sun();
    std::mt19937 rng(3);
    int checked = 0;
    double worst = 0.0;
    // Vertex (i, j, k) lies where the ray coordinates are integers: solve for the point.
    const SunDepthMap::Ray at_origin = map.ray(u);  // u0, v0, s0: the origin's lattice coordinates
    for (int n = 0; n < 400; ++n) {
        const int i = 1 + int(rng() % unsigned(map.size_u() - 2)), j = 1 + int(rng() % unsigned(map.size_v() - 2));
        const int k = int(rng() % unsigned(map.size_s()));
        const double c = double(map.cell());
        // Lattice coordinates relative to the origin: g = g0 + (x - eye) . axis / cell.
        const glm::dvec3 rel = (double(i) - at_origin.u0) * c * u + (double(j) - at_origin.v0) * c * v +
                               (double(k) - at_origin.s0) * double(map.cell()) * l;
        const double t = glm::length(rel);
        if (t < 1e-6) continue;
        const double got = map.optical_depth(map.ray(rel / t), float(t));
        const double want = sun.optical_depth(eye + rel);
        worst = std::max(worst, std::abs(got - want));
        ++checked;
    }
    EXPECT_GT(checked, 300);
    // Float coordinates land a rounding error from the vertex: the slope (at most tau_max per unit s)
    // times that error, plus the float sum.
    EXPECT_LT(worst, 2e-3) << "worst vertex error";
}

// Between vertices the error is the interpolation's: it falls as the lattice is refined (the smaller
// budgets force a coarser cell), and at the default resolution it is small.
TEST(SunDepthMap, ConvergesAsTheLatticeIsRefined) {
    // Thin spheres (tau r below 1), so that more than kMaxWholeSpheres of them are a lattice (a dense
    // cloud of as few takes columns), its spacing widened by 1 / (tau r)^2 of their 99th percentile (at
    // most twice).
    Scene s = random_cloud(80, 11, {-0.3, -1.0, 0.5});
    for (Sphere& sp : s.spheres) sp.extinction *= 0.4;
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const SunLight sun(s);
    ASSERT_FALSE(SunDepthMap(s, sun, eye, 1).has_columns());
    const std::vector<Probe> ps = probes(4000, 5);
    double previous = 1e9;
    // Budgets that bind (the spacing widened to fit them), then the map's own spacing (75 x 75 x 62).
    for (const std::size_t budget : {std::size_t(5000), std::size_t(20000), std::size_t(2000000)}) {
        const SunDepthMap map(s, sun, eye, 2, budget);
        EXPECT_LE(std::size_t(map.size_u()) * map.size_v() * map.size_s(), budget);
        double sum = 0.0, depth_sum = 0.0;
        for (const Probe& p : ps) {
            const double want = sun.optical_depth(eye + p.t * p.d);
            sum += std::abs(double(map.optical_depth(map.ray(p.d), float(p.t))) - want);
            depth_sum += want;
        }
        const double mean = sum / double(ps.size());
        std::printf("  budget %zu: %dx%dx%d, mean error %.3g, mean depth %.3g\n", budget, map.size_u(), map.size_v(),
                    map.size_s(), mean, depth_sum / double(ps.size()));
        EXPECT_LT(mean, 0.7 * previous) << "budget " << budget;
        previous = mean;
        // At the map's own spacing (reached within this budget) the mean error is below 1e-3 in optical
        // depth, so below 1e-3 relative in T_sun = exp(-depth).
        if (budget == 2000000) {
            EXPECT_LT(mean, 1e-3);
        }
    }
}

TEST(SunDepthMap, TheSameForAnyThreadCount) {
    const Scene s = random_cloud(kLatticeSpheres, 13, {0.2, -1.0, -0.4});
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const SunLight sun(s);
    const SunDepthMap one(s, sun, eye, 1), four(s, sun, eye, 4);
    ASSERT_EQ(one.size_u(), four.size_u());
    for (const Probe& p : probes(2000, 9)) {
        const float a = one.optical_depth(one.ray(p.d), float(p.t)), b = four.optical_depth(four.ray(p.d), float(p.t));
        ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    }
}

bool same_map(const SunDepthMap& a, const SunDepthMap& b) {
    return a.size_u() == b.size_u() && a.size_v() == b.size_v() && a.size_s() == b.size_s() &&
           a.values().size() == b.values().size() &&
           std::memcmp(a.values().data(), b.values().data(), a.values().size_bytes()) == 0;
}

// The splat runs on AVX-512's scatters or on AVX2 where the CPU has them, and on any x86-64's
// instructions otherwise: the same float operations, so the same map bit for bit: on a cloud, and on
// one where a few spheres are six times the others' size (their chords span dozens of cells, and
// the scatters' whole-cell runs are many).
TEST(SunDepthMap, PortableInstructionsBuildTheSameMap) {
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    Scene large = random_cloud(kLatticeSpheres, 41, {0.3, -1.0, 0.2});
    for (std::size_t k = 0; k < 6; ++k) large.spheres[k].radius *= 6.0;
    for (const Scene& s : {random_cloud(kLatticeSpheres + 100, 40, {-0.2, -1.0, 0.4}), large}) {
        const SunLight sun(s);
        const SunDepthMap best(s, sun, eye, 2, SunDepthMap::kDefaultMaxVertices, MapInstructions::Best);
        const SunDepthMap avx2(s, sun, eye, 2, SunDepthMap::kDefaultMaxVertices, MapInstructions::Avx2);
        const SunDepthMap portable(s, sun, eye, 2, SunDepthMap::kDefaultMaxVertices, MapInstructions::Portable);
        ASSERT_FALSE(best.empty());
        EXPECT_TRUE(same_map(best, portable));
        EXPECT_TRUE(same_map(avx2, portable));
    }
}

TEST(SunDepthMap, BuiltAgainInPlaceIsAFreshMap) {
    // An owner keeps its map from frame to frame (its memory and its workers' scratch, which a build
    // must leave zero): each build must equal a fresh map of the same scene, bit for bit, whether the
    // lattice keeps its shape (the same scene again), changes it (another scene), or is empty.
    const Scene first = random_cloud(kLatticeSpheres, 21, {0.2, -1.0, -0.4});
    Scene second = random_cloud(2 * kLatticeSpheres, 22, {-0.5, -1.0, 0.1});
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    SunDepthMap kept;
    for (int threads : {1, 3}) {
        for (const Scene* s : std::initializer_list<const Scene*>{&first, &first, &second, &first}) {
            kept.build(*s, SunLight(*s), eye, threads);
            const SunDepthMap fresh(*s, SunLight(*s), eye, threads);
            ASSERT_FALSE(fresh.empty());
            EXPECT_TRUE(same_map(kept, fresh)) << threads << " threads";
        }
    }
    Scene off = first;
    off.lighting.shadows = false;
    kept.build(off, SunLight(off), eye, 2);
    EXPECT_TRUE(kept.empty());
    for (const Probe& p : probes(200, 5)) EXPECT_EQ(kept.optical_depth(kept.ray(p.d), float(p.t)), 0.0f);
    kept.build(second, SunLight(second), eye, 2);
    EXPECT_TRUE(same_map(kept, SunDepthMap(second, SunLight(second), eye, 2)));
}

// An owner's map built again in place as its scene changes layout (columns, a lattice, every sphere
// whole, no shadows, columns again, as an emitter's cloud grows past kMaxWholeSpheres and
// kMaxColumnSpheres and back) reads what a fresh map of each reads, bit for bit, and has columns
// exactly when the fresh one does: nothing of one layout's lookup is left in the next.
TEST(SunDepthMap, BuiltAgainInPlaceAcrossLayoutsIsAFreshMap) {
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const Scene columns = random_cloud(120, 61, {0.3, -1.0, 0.4});
    const Scene lattice = random_cloud(kLatticeSpheres, 62, {0.3, -1.0, 0.4});
    const Scene whole = random_cloud(30, 63, {0.3, -1.0, 0.4});
    Scene off = columns;
    off.lighting.shadows = false;
    const Scene other_columns = random_cloud(200, 64, {-0.2, -1.0, 0.3});
    const std::vector<Probe> ps = probes(800, 65);
    SunDepthMap kept;
    int with_columns = 0;
    for (const Scene* s : std::initializer_list<const Scene*>{&columns, &lattice, &columns, &whole, &off, &other_columns, &lattice}) {
        kept.build(*s, SunLight(*s), eye, 2);
        const SunDepthMap fresh(*s, SunLight(*s), eye, 2);
        ASSERT_EQ(kept.has_columns(), fresh.has_columns());
        ASSERT_EQ(kept.empty(), fresh.empty());
        ASSERT_EQ(kept.outsized().size(), fresh.outsized().size());
        with_columns += kept.has_columns() ? 1 : 0;
        for (const Probe& p : ps)
            ASSERT_EQ(std::bit_cast<std::uint32_t>(kept.optical_depth(kept.ray(p.d), float(p.t))),
                      std::bit_cast<std::uint32_t>(fresh.optical_depth(fresh.ray(p.d), float(p.t))));
    }
    EXPECT_EQ(with_columns, 3);
}

TEST(SunDepthMap, BuiltAgainAsAnAnimationGrowsAndShrinksIsAFreshMap) {
    // Playback: the smoke spreads and gathers from frame to frame, so the lattice changes its shape
    // (on every axis, up and down) and its size, within the room the map keeps and past it. Each
    // build must still equal a fresh map bit for bit: the kept scratch is all zero after a build in
    // any shape, and a column's "no chord" bottom follows the number of vertices along s.
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    SunDepthMap kept;
    int shape_changes = 0, grew = 0, shrank = 0;
    std::size_t last_size = 0;
    int last_ns = 0;
    for (double spread : {1.0, 1.08, 1.2, 1.1, 1.35, 0.9, 1.5, 1.45, 1.0}) {
        Scene s = random_cloud(kLatticeSpheres, 31, {0.3, -1.0, -0.2});
        for (Sphere& sp : s.spheres) sp.center = glm::dvec3(sp.center.x * spread, sp.center.y, sp.center.z / spread);
        kept.build(s, SunLight(s), eye, 2);
        const SunDepthMap fresh(s, SunLight(s), eye, 2);
        ASSERT_FALSE(fresh.empty());
        EXPECT_TRUE(same_map(kept, fresh)) << "spread " << spread;
        if (last_ns != 0 && kept.size_s() != last_ns) ++shape_changes;
        if (last_size != 0) (kept.values().size() > last_size ? grew : shrank) += kept.values().size() != last_size;
        last_ns = kept.size_s();
        last_size = kept.values().size();
    }
    // The sequence did what it is for.
    EXPECT_GE(shape_changes, 3);
    EXPECT_GE(grew, 2);
    EXPECT_GE(shrank, 2);
}

// A cloud inside a fog sphere of radius 10,000: the fog is an outsized sphere (over 16 times the median
// radius), taken in closed form at each lookup, so the lattice keeps the cloud's own spacing and
// extent, and a lookup's error (scalar and eight at a time) is what it is without the fog. In the
// lattice the fog's radius set the spacing (about 225 units) and the cloud's shadows were lost.
TEST(SunDepthMap, AnOutsizedSphereIsTakenInClosedForm) {
    Scene cloud = random_cloud(kLatticeSpheres, 11, {-0.3, -1.0, 0.5});
    Scene fogged = cloud;
    Sphere fog;
    fog.center = {3.0, -20.0, 7.0};
    fog.radius = 1e4;
    fog.extinction = 1e-4;
    fogged.spheres.insert(fogged.spheres.begin() + 5, fog);
    const glm::dvec3 eye(0.0, 1.0, -8.0);
    const SunLight cloud_sun(cloud), fogged_sun(fogged);
    const SunDepthMap plain(cloud, cloud_sun, eye, 2), map(fogged, fogged_sun, eye, 2);
    ASSERT_EQ(map.outsized().size(), 1u);
    EXPECT_TRUE(plain.outsized().empty());
    EXPECT_EQ(map.cell(), plain.cell());
    EXPECT_EQ(map.size_u() * map.size_v() * map.size_s(), plain.size_u() * plain.size_v() * plain.size_s());
    const std::vector<Probe> ps = probes(4000, 5);
    double plain_error = 0.0, error = 0.0, fog_depth = 0.0;
    for (const Probe& p : ps) {
        const glm::dvec3 x = eye + p.t * p.d;
        plain_error += std::abs(double(plain.optical_depth(plain.ray(p.d), float(p.t))) - cloud_sun.optical_depth(x));
        const double want = fogged_sun.optical_depth(x);
        error += std::abs(double(map.optical_depth(map.ray(p.d), float(p.t))) - want);
        fog_depth += want - cloud_sun.optical_depth(x);
    }
    const double n = double(ps.size());
    std::printf("  mean error %.3g with the fog (its mean depth %.3g), %.3g without it\n", error / n, fog_depth / n,
                plain_error / n);
    EXPECT_GT(fog_depth / n, 0.5) << "the fog should shade the cloud";
    EXPECT_LT(error / n, 1.1 * plain_error / n + 1e-4);
    // Eight at a time (the tracer's lanes): the scalar lookup's values.
    const LatticePoints g = lattice_points(map, ps);
    std::vector<float> batch(ps.size());
    map.optical_depths(g.gu.data(), g.gv.data(), g.gs.data(), batch.data(), ps.size(), simd::GatherByLanes{});
    for (std::size_t k = 0; k < ps.size(); ++k)
        EXPECT_NEAR(batch[k], map.optical_depth(map.ray(ps[k].d), float(ps[k].t)), 1e-5 * (1.0 + batch[k])) << k;
}

}  // namespace
}  // namespace brume
