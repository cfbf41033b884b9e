// Density sampling (sim/density_sampler.h) and density-seeded emitters: samples follow the grid's
// trilinear field exactly (a chi-square test against exact box integrals, and the exact moments), the
// transform places them, and a grid that was never loaded is a clear error, not a crash.
#include "sim/density_sampler.h"
#include "sim/emitters.h"
#include "sim/rng.h"
#include "sim/simulator.h"
#include "sim/volume_transform.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {
namespace {

constexpr int kSamples = 200'000;

// Small and lopsided: zeros inside and on the rim, values spanning a factor of 20, an origin and index
// range off zero, so a transposed axis, an offset error or a wrong tent would show.
DensityGrid small_grid() {
    DensityGrid g;
    g.name = "small";
    g.origin = {0.3, -0.2, 0.1};
    g.voxel_size = 0.5;
    g.min = {-1, 2, 0};
    g.size = {3, 3, 2};
    g.values = {1.0f, 2.0f, 0.0f,  4.0f, 0.5f, 3.0f, 0.0f, 1.0f, 2.0f,
                5.0f, 0.0f, 1.5f, 2.0f, 0.25f, 3.0f, 0.0f, 1.0f, 4.0f};
    for (float v : g.values) g.active_voxels += v != 0.0f;
    return g;
}

// Four reproducible uniforms per sample.
struct Uniforms {
    double u[4];
};
Uniforms uniforms(std::uint64_t i) {
    const std::uint64_t key = rng::hash(0x64656e73ull, 2024, i);  // "dens"
    return {{rng::uniform(key, 0), rng::uniform(key, 1), rng::uniform(key, 2), rng::uniform(key, 3)}};
}

std::vector<glm::dvec3> draw(const DensitySampler& s, int n) {
    std::vector<glm::dvec3> out(std::size_t(n), glm::dvec3(0.0));
    for (int i = 0; i < n; ++i) {
        const Uniforms r = uniforms(std::uint64_t(i));
        out[std::size_t(i)] = s.sample(r.u[0], r.u[1], r.u[2], r.u[3]);
    }
    return out;
}

// Position in the grid's index space relative to min: voxel centres at integers, support [-1, size].
glm::dvec3 local(const DensityGrid& g, const glm::dvec3& world) {
    return (world - g.origin) / g.voxel_size - glm::dvec3(g.min);
}
glm::dvec3 world(const DensityGrid& g, const glm::dvec3& local) { return g.voxel_center(local); }

// Half-voxel boxes over the support. Each lies inside one cell between voxel centres, where the field
// is trilinear, so the midpoint rule gives its integral exactly: an expectation computed from
// DensityGrid::sample alone, independent of how the sampler works.
struct Bins {
    glm::ivec3 n;
    std::vector<double> mass;  // integral of the field over each box
    std::size_t index(const glm::ivec3& b) const {
        return (std::size_t(b.z) * std::size_t(n.y) + std::size_t(b.y)) * std::size_t(n.x) + std::size_t(b.x);
    }
};
Bins half_voxel_bins(const DensityGrid& g) {
    Bins bins;
    bins.n = 2 * (g.size + 1);
    bins.mass.resize(std::size_t(bins.n.x) * std::size_t(bins.n.y) * std::size_t(bins.n.z));
    const double volume = std::pow(g.voxel_size / 2.0, 3);
    for (int k = 0; k < bins.n.z; ++k)
        for (int j = 0; j < bins.n.y; ++j)
            for (int i = 0; i < bins.n.x; ++i) {
                const glm::dvec3 centre = -1.0 + (glm::dvec3(i, j, k) + 0.5) * 0.5;
                bins.mass[bins.index({i, j, k})] = g.sample(world(g, centre)) * volume;
            }
    return bins;
}

// Pearson's statistic over the bins, those expecting fewer than 10 pooled into one, and its degrees of
// freedom.
struct ChiSquare {
    double statistic = 0.0;
    int dof = 0;
};
ChiSquare chi_square(const DensityGrid& g, const Bins& bins, const std::vector<glm::dvec3>& points) {
    std::vector<double> observed(bins.mass.size(), 0.0);
    for (const glm::dvec3& p : points) {
        const glm::ivec3 b = glm::ivec3(glm::floor((local(g, p) + 1.0) * 2.0));
        EXPECT_TRUE(b.x >= 0 && b.y >= 0 && b.z >= 0 && b.x < bins.n.x && b.y < bins.n.y && b.z < bins.n.z)
            << "a sample outside the support";
        observed[bins.index(glm::clamp(b, glm::ivec3(0), bins.n - 1))] += 1.0;
    }
    double total = 0.0;
    for (double m : bins.mass) total += m;
    ChiSquare c;
    double pooled_expected = 0.0, pooled_observed = 0.0;
    for (std::size_t i = 0; i < bins.mass.size(); ++i) {
        const double expected = double(points.size()) * bins.mass[i] / total;
        if (expected < 10.0) {
            pooled_expected += expected;
            pooled_observed += observed[i];
            continue;
        }
        c.statistic += (observed[i] - expected) * (observed[i] - expected) / expected;
        ++c.dof;
    }
    if (pooled_expected > 0.0) {
        c.statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
        ++c.dof;
    }
    --c.dof;  // the counts sum to the number of samples
    return c;
}

// The chi-square quantile with upper tail 1e-6 (Wilson-Hilferty; z = 4.753): a correct sampler with a
// fixed seed fails with probability 1e-6, so a failure means a wrong distribution.
double chi_square_limit(int dof) {
    const double k = dof, z = 4.753;
    return k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3);
}

// Exact mass, mean and covariance of the field: Simpson's rule on every cell between voxel centres,
// exact because x * field and x^2 * field are at most cubic along each axis there.
struct Moments {
    double mass = 0.0;
    glm::dvec3 mean{0.0};
    glm::dmat3 covariance{0.0};
};
Moments exact_moments(const DensityGrid& g) {
    constexpr double kNode[3] = {0.0, 0.5, 1.0};
    constexpr double kWeight[3] = {1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0};
    const double cell_volume = std::pow(g.voxel_size, 3);
    double m0 = 0.0;
    glm::dvec3 m1(0.0);
    glm::dmat3 m2(0.0);
    for (int ck = -1; ck < g.size.z; ++ck)
        for (int cj = -1; cj < g.size.y; ++cj)
            for (int ci = -1; ci < g.size.x; ++ci)
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        for (int c = 0; c < 3; ++c) {
                            const glm::dvec3 x = world(g, glm::dvec3(ci + kNode[a], cj + kNode[b], ck + kNode[c]));
                            const double w = kWeight[a] * kWeight[b] * kWeight[c] * cell_volume * g.sample(x);
                            m0 += w;
                            m1 += w * x;
                            for (int r = 0; r < 3; ++r)
                                for (int s = 0; s < 3; ++s) m2[s][r] += w * x[r] * x[s];
                        }
    Moments m;
    m.mass = m0;
    m.mean = m1 / m0;
    for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) m.covariance[s][r] = m2[s][r] / m0 - m.mean[r] * m.mean[s];
    return m;
}

TEST(TentOffset, InvertsTheTentCdf) {
    EXPECT_EQ(tent_offset(0.0), -1.0);
    EXPECT_EQ(tent_offset(0.5), 0.0);
    EXPECT_NEAR(tent_offset(std::nextafter(1.0, 0.0)), 1.0, 1e-7);
    double previous = -2.0;
    for (int i = 0; i <= 1000; ++i) {
        const double t = -1.0 + 2.0 * i / 1000.0;
        const double cdf = t < 0.0 ? 0.5 * (1.0 + t) * (1.0 + t) : 1.0 - 0.5 * (1.0 - t) * (1.0 - t);
        if (cdf < 1.0) {
            EXPECT_NEAR(tent_offset(cdf), t, 1e-7) << t;
        }
        const double u = i / 1001.0;
        EXPECT_GT(tent_offset(u), previous);
        previous = tent_offset(u);
    }
}

TEST(DensitySampler, MassAndGridAreTheGrids) {
    const DensityGrid g = small_grid();
    const DensitySampler s(g);
    EXPECT_EQ(s.mass(), g.mass());
    EXPECT_EQ(s.grid().values, g.values);
    EXPECT_EQ(s.grid().name, "small");
    EXPECT_NEAR(exact_moments(g).mass, g.mass(), 1e-12 * g.mass()) << "the quadrature is exact";
}

TEST(DensitySampler, FollowsTheTrilinearFieldChiSquare) {
    const DensityGrid g = small_grid();
    const Bins bins = half_voxel_bins(g);
    double total = 0.0;
    for (double m : bins.mass) total += m;
    ASSERT_NEAR(total, g.mass(), 1e-12 * g.mass()) << "the bins cover the support exactly";

    const std::vector<glm::dvec3> points = draw(DensitySampler(g), kSamples);
    const ChiSquare c = chi_square(g, bins, points);
    ASSERT_GT(c.dof, 100);
    EXPECT_LT(c.statistic, chi_square_limit(c.dof)) << "dof " << c.dof;

    // The test has teeth: the right voxels with a uniform offset instead of the tent (the field of
    // nearest-voxel boxes, with the same mass per voxel) is rejected by a wide margin.
    const DensitySampler s(g);
    std::vector<glm::dvec3> boxes(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Uniforms r = uniforms(i);
        boxes[i] = s.sample(r.u[0], 0.5, 0.5, 0.5) + g.voxel_size * (glm::dvec3(r.u[1], r.u[2], r.u[3]) - 0.5);
    }
    const ChiSquare wrong = chi_square(g, bins, boxes);
    EXPECT_GT(wrong.statistic, 10.0 * chi_square_limit(wrong.dof));
}

TEST(DensitySampler, MomentsMatchTheExactOnes) {
    const DensityGrid g = small_grid();
    const Moments exact = exact_moments(g);
    const std::vector<glm::dvec3> points = draw(DensitySampler(g), kSamples);
    const double n = double(points.size());
    glm::dvec3 mean(0.0);
    for (const glm::dvec3& p : points) mean += p;
    mean /= n;
    for (int a = 0; a < 3; ++a) {
        const double standard_error = std::sqrt(exact.covariance[a][a] / n);
        EXPECT_NEAR(mean[a], exact.mean[a], 5.0 * standard_error) << "axis " << a;
    }
    // Each covariance entry against its own standard error, estimated from the same samples.
    for (int r = 0; r < 3; ++r)
        for (int s = r; s < 3; ++s) {
            double sum = 0.0, sum_sq = 0.0;
            for (const glm::dvec3& p : points) {
                const double v = (p[r] - exact.mean[r]) * (p[s] - exact.mean[s]);
                sum += v;
                sum_sq += v * v;
            }
            const double estimate = sum / n;
            const double standard_error = std::sqrt((sum_sq / n - estimate * estimate) / n);
            EXPECT_NEAR(estimate, exact.covariance[s][r], 5.0 * standard_error) << "entry " << r << s;
        }
    // The moments the mixture predicts: voxel centres weighted by value, plus the tent's variance
    // (voxel_size^2 / 6) on each axis, independently. A cross-check of the quadrature above.
    double weight = 0.0;
    glm::dvec3 centre_mean(0.0);
    for (int k = 0; k < g.size.z; ++k)
        for (int j = 0; j < g.size.y; ++j)
            for (int i = 0; i < g.size.x; ++i) {
                weight += g.at(i, j, k);
                centre_mean += double(g.at(i, j, k)) * g.voxel_center(glm::dvec3(i, j, k));
            }
    centre_mean /= weight;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(exact.mean[a], centre_mean[a], 1e-12);
}

TEST(DensitySampler, TheTransformPlacesEverySample) {
    const DensityGrid g = small_grid();
    VolumeTransform t;
    t.translate = {1.0, -2.0, 3.5};
    t.scale = 2.5;
    t.rotate_deg = {30.0, -45.0, 60.0};
    const DensitySampler plain(g), placed(g, t);
    EXPECT_EQ(placed.mass(), plain.mass()) << "mass is in the grid's own units";
    for (std::uint64_t i = 0; i < 2000; ++i) {
        const Uniforms r = uniforms(i);
        const glm::dvec3 a = volume_to_world(t, plain.sample(r.u[0], r.u[1], r.u[2], r.u[3]));
        const glm::dvec3 b = placed.sample(r.u[0], r.u[1], r.u[2], r.u[3]);
        ASSERT_LT(glm::length(a - b), 1e-12 * (1.0 + glm::length(a))) << i;
        // And the world position maps back into the grid's support.
        const glm::dvec3 q = local(g, world_to_volume(t, b));
        ASSERT_TRUE(q.x >= -1.0 - 1e-9 && q.y >= -1.0 - 1e-9 && q.z >= -1.0 - 1e-9) << i;
        ASSERT_TRUE(q.x <= g.size.x + 1e-9 && q.y <= g.size.y + 1e-9 && q.z <= g.size.z + 1e-9) << i;
    }
}

TEST(DensitySampler, ExtremeUniformsStayInTheSupport) {
    const DensityGrid g = small_grid();
    const DensitySampler s(g);
    const double top = std::nextafter(1.0, 0.0);
    for (double u0 : {0.0, top})
        for (double u : {0.0, top}) {
            const glm::dvec3 q = local(g, s.sample(u0, u, u, u));
            for (int a = 0; a < 3; ++a) {
                EXPECT_GE(q[a], -1.0 - 1e-12);
                EXPECT_LE(q[a], g.size[a] + 1e-12);
            }
        }
    // u0 = 0 picks the first positive voxel, u0 just below 1 the last.
    EXPECT_LT(glm::length(local(g, s.sample(0.0, 0.5, 0.5, 0.5)) - glm::dvec3(0, 0, 0)), 1e-12);
    EXPECT_LT(glm::length(local(g, s.sample(top, 0.5, 0.5, 0.5)) - glm::dvec3(2, 2, 1)), 1e-12);
}

TEST(DensitySampler, RefusesAGridWithoutDensity) {
    DensityGrid zeros = small_grid();
    std::fill(zeros.values.begin(), zeros.values.end(), 0.0f);
    try {
        DensitySampler s(zeros);
        FAIL() << "sampled a grid of zeros";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("grid \"small\" holds no positive density"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(DensitySampler(DensityGrid{}), std::invalid_argument) << "an empty grid";
    VolumeTransform flat;
    flat.scale = 0.0;
    EXPECT_THROW(DensitySampler(small_grid(), flat), std::invalid_argument);
}

// --- Emitters -------------------------------------------------------------------------------------

EmitterDesc density_emitter(std::shared_ptr<const DensitySampler> sampler) {
    EmitterDesc e;
    e.name = "seeded";
    e.shape = EmitterShape::Density;
    e.density_source.file = "builtin:cloud";
    e.density = std::move(sampler);
    e.speed = {0.5, 2.0};
    e.cone_deg = 30.0;
    e.jitter = 0.2;
    e.lifetime = {1.0, 3.0};
    e.radius_range = {0.05, 0.1};
    e.extinction = {1.0, 2.0};
    e.albedo = {{0.2, 0.3, 0.4}, {0.6, 0.7, 0.8}};
    e.bursts = {{0.0, 100}};
    return e;
}

TEST(DensityEmitter, BirthsFollowTheField) {
    const DensityGrid g = small_grid();
    VolumeTransform t;
    t.translate = {0.0, 1.0, 0.0};
    t.scale = 0.5;
    t.rotate_deg = {0.0, 90.0, 0.0};
    const EmitterDesc e = density_emitter(std::make_shared<const DensitySampler>(g, t));
    const Moments exact = exact_moments(g);
    const int n = 20'000;
    glm::dvec3 mean(0.0);
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 p = sample_particle(e, 7, 3, std::uint64_t(i)).position;
        const glm::dvec3 q = local(g, world_to_volume(t, p));
        ASSERT_TRUE(q.x >= -1.0 - 1e-6 && q.y >= -1.0 - 1e-6 && q.z >= -1.0 - 1e-6) << i;
        ASSERT_TRUE(q.x <= g.size.x + 1e-6 && q.y <= g.size.y + 1e-6 && q.z <= g.size.z + 1e-6) << i;
        mean += world_to_volume(t, p);
    }
    mean /= double(n);
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mean[a], exact.mean[a], 5.0 * std::sqrt(exact.covariance[a][a] / n)) << "axis " << a;
}

TEST(DensityEmitter, OtherDrawsAreThoseOfAnyShape) {
    // The density shape's extra draw has a slot of its own, after all the others: velocity, lifetime,
    // radius, extinction and albedo are the draws every other shape makes for the same particle.
    EmitterDesc density = density_emitter(std::make_shared<const DensitySampler>(small_grid()));
    EmitterDesc point = density;
    point.shape = EmitterShape::Point;
    point.density = nullptr;
    for (std::uint64_t i = 0; i < 200; ++i) {
        const Particle a = sample_particle(density, 11, 2, i), b = sample_particle(point, 11, 2, i);
        EXPECT_EQ(a.velocity, b.velocity);
        EXPECT_EQ(a.lifetime, b.lifetime);
        EXPECT_EQ(a.radius, b.radius);
        EXPECT_EQ(a.extinction, b.extinction);
        EXPECT_EQ(a.albedo, b.albedo);
        EXPECT_EQ(a.id, b.id);
    }
}

TEST(DensityEmitter, AGridNotLoadedIsAClearError) {
    const EmitterDesc e = density_emitter(nullptr);
    const std::string message = "emitter \"seeded\": its density grid was not loaded (call load_emitter_densities)";
    try {
        sample_particle(e, 1, 0, 0);
        FAIL() << "sampled a density emitter without a grid";
    } catch (const std::logic_error& error) {
        EXPECT_EQ(std::string(error.what()), message);
    }
    Preset p;
    p.emitters.push_back(e);
    try {
        Simulator sim(p);
        FAIL() << "simulated a density emitter without a grid";
    } catch (const std::logic_error& error) {
        EXPECT_EQ(std::string(error.what()), message);
    }
    // Loaded, the same preset simulates.
    p.emitters[0].density = std::make_shared<const DensitySampler>(small_grid());
    Simulator sim(p);
    EXPECT_EQ(sim.particles().size(), 100u);
}

}  // namespace
}  // namespace brume
