// Spheres back to a density grid (sim/vdb/particle_splat.h, `brume vdb-export`): every sphere's extinction
// mass lands in the grid, the grid's optical depth matches the spheres', the grids survive a .vdb round
// trip, import (sim/vdb/vdb_import.h) of an export gives the spheres' mass and optical depth back, and bad
// input is refused with a message naming it.
#include "sim/vdb/particle_splat.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/vdb_file.h"
#include "sim/vdb/vdb_import.h"

#include "tests/test_scenes.h"
#include "tests/vdb_test_samples.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

namespace brume {
namespace {

using namespace vdb_test;

constexpr double kPi = std::numbers::pi;

using testing::sphere;

SplatOptions at_voxel(double voxel_size) {
    SplatOptions o;
    o.voxel_size = voxel_size;
    return o;
}

// Optical depth of the grid's trilinear field (times extinction_scale) along the z line through (x, y):
// along it the field is linear between voxel-centre planes and 0 at the support's ends, so the sum of its
// values at those planes times the voxel size is the exact integral.
double grid_depth_z(const DensityGrid& g, double extinction_scale, double x, double y) {
    double sum = 0.0;
    for (int k = -1; k <= g.size.z; ++k) {
        const double z = g.voxel_center(glm::dvec3(0, 0, k)).z;
        sum += g.sample({x, y, z});
    }
    return sum * g.voxel_size * extinction_scale;
}

// The spheres' optical depth along the z line through (x, y): extinction times chord.
double spheres_depth_z(const std::vector<Sphere>& spheres, double x, double y) {
    double sum = 0.0;
    for (const Sphere& s : spheres) {
        const double d2 = (x - s.center.x) * (x - s.center.x) + (y - s.center.y) * (y - s.center.y);
        if (d2 < s.radius * s.radius) sum += s.extinction * 2.0 * std::sqrt(s.radius * s.radius - d2);
    }
    return sum;
}

// A smoke-like frame: `count` spheres of radius 0.05-0.2 and extinction 0.5-4 in a blob about the origin,
// albedo varying per sphere. Deterministic.
std::vector<Sphere> puff(int count, unsigned seed = 5) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Sphere> out;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 p{u(rng) - 0.5, 0.8 * (u(rng) - 0.5), 0.6 * (u(rng) - 0.5)};
        out.push_back(sphere(p, 0.05 + 0.15 * u(rng), 0.5 + 3.5 * u(rng), {u(rng), u(rng), u(rng)}));
    }
    return out;
}

// The grid's extinction mass is the spheres' to 1e-9 relative, or, for a grid of a handful of voxels, to the
// float spacing of its largest value: no float grid can do better.
void expect_mass(const DensityGrid& g, double extinction_scale, const std::vector<Sphere>& spheres) {
    const double want = spheres_extinction_mass(spheres);
    const float largest = *std::max_element(g.values.begin(), g.values.end());
    const double spacing = (std::nextafter(largest, INFINITY) - largest) * std::pow(g.voxel_size, 3) * extinction_scale;
    EXPECT_NEAR(g.mass() * extinction_scale, want, std::max(1e-9 * want, spacing));
}

// The message of the std::invalid_argument that splatting throws; fails the test when none is thrown.
std::string splat_error(const std::vector<Sphere>& spheres, const SplatOptions& o) {
    try {
        splat_spheres(spheres, o);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    ADD_FAILURE() << "no std::invalid_argument";
    return "";
}

// --- Mass: each sphere deposits exactly its extinction mass. --------------------------------------------

TEST(VdbSplatMass, SphereOnAVoxelCentre) {
    const std::vector<Sphere> s{sphere({0.0, 0.0, 0.0}, 0.37, 2.0)};
    const DensityGrid g = spheres_to_density_grid(s, at_voxel(0.05));
    expect_mass(g, 1.0, s);
    // Symmetric about its centre voxel, and the interior is the sphere's extinction.
    EXPECT_NEAR(g.sample({0, 0, 0}), 2.0, 2e-3);
    EXPECT_EQ(g.sample({0.25, 0, 0}), g.sample({-0.25, 0, 0}));
}

TEST(VdbSplatMass, SphereOffTheVoxelCentres) {
    // Off centre, on a voxel corner (symmetric: every voxel rounds alike), and far from the origin.
    for (const glm::dvec3 c :
         {glm::dvec3(0.0123, -0.0371, 0.0219), glm::dvec3(0.025, 0.025, 0.025), glm::dvec3(-3.3, 7.1, 0.4)}) {
        for (const double r : {0.03, 0.07, 0.15, 0.37}) {  // 0.6 to 7.4 voxels
            const std::vector<Sphere> s{sphere(c, r, 1.5)};
            const DensityGrid g = spheres_to_density_grid(s, at_voxel(0.05));
            SCOPED_TRACE(r);
            expect_mass(g, 1.0, s);
        }
    }
}

TEST(VdbSplatMass, SubVoxelSphereDepositsTrilinearWeightsAroundItsCentre) {
    const glm::dvec3 c{0.0123, -0.0371, 0.0219};
    const std::vector<Sphere> s{sphere(c, 0.01, 40.0)};  // a fifth of a voxel across
    const DensityGrid g = spheres_to_density_grid(s, at_voxel(0.05));
    EXPECT_EQ(g.size, glm::ivec3(2));
    EXPECT_EQ(g.active_voxels, 8u);
    expect_mass(g, 1.0, s);
    // The hats reproduce linear functions: the field's centre of mass is the sphere's centre.
    glm::dvec3 moment{0.0};
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) moment += double(g.at(i, j, k)) * g.voxel_center(glm::dvec3(i, j, k));
    const glm::dvec3 centroid = moment * std::pow(g.voxel_size, 3) / g.mass();
    EXPECT_NEAR(glm::length(centroid - c), 0.0, 1e-7);
}

TEST(VdbSplatMass, BigSphereIsUniformInsideAndExactInTotal) {
    // 40 voxels of radius: 81^3 voxels.
    const std::vector<Sphere> s{sphere({0.1, -0.2, 0.3}, 1.0, 0.75)};
    SplatOptions o = at_voxel(0.025);
    o.extinction_scale = 0.25;  // density = 3
    const DensityGrid g = spheres_to_density_grid(s, o);
    expect_mass(g, 0.25, s);
    // Inside, every voxel is the density to within the rescale of the subsampled edge (measured 1.2e-5).
    for (const glm::dvec3 p : {glm::dvec3(0.1, -0.2, 0.3), glm::dvec3(0.6, -0.2, 0.3), glm::dvec3(0.1, 0.3, 0.0)})
        EXPECT_NEAR(g.sample(p), 3.0, 3e-4) << p.x << " " << p.y << " " << p.z;
    EXPECT_EQ(g.sample({1.2, -0.2, 0.3}), 0.0);
}

TEST(VdbSplatMass, ManySpheresAndTheExtinctionScale) {
    const std::vector<Sphere> spheres = puff(400);
    SplatOptions o;
    o.resolution = 64;
    o.extinction_scale = 2.5;
    const SplatGrids grids = splat_spheres(spheres, o);
    EXPECT_EQ(grids.spheres, spheres.size());
    EXPECT_NEAR(grids.sphere_mass, spheres_extinction_mass(spheres), 1e-12 * grids.sphere_mass);
    expect_mass(grids.density, 2.5, spheres);
}

// --- Where the voxels are. ----------------------------------------------------------------------------

TEST(VdbSplatLattice, VoxelsAreAnchoredAtTheOriginAndResolutionSpansTheLongestSide) {
    const std::vector<Sphere> s{sphere({0.3, 0.1, 0.0}, 0.5, 1.0), sphere({2.3, 0.2, 0.1}, 0.5, 1.0)};
    SplatOptions o;
    o.resolution = 30;  // the box is 3 long in x
    const DensityGrid g = spheres_to_density_grid(s, o);
    // 0.1 would give 31 voxels (the lattice starts at the origin, not at the box): the voxel widens
    // until the longest side holds 30.
    EXPECT_GT(g.voxel_size, 0.1);
    EXPECT_LT(g.voxel_size, 0.1 * 31.0 / 30.0 * 1.001);
    EXPECT_EQ(g.origin, glm::dvec3(0.0));  // a pure-scale transform: frames at one voxel size share voxels
    EXPECT_EQ(g.size.x, 30);
    EXPECT_LE(g.size.y, 12);
    EXPECT_EQ(g.name, "density");
    // Other resolutions never exceed what was asked.
    for (int resolution : {8, 9, 64, 128}) {
        o.resolution = resolution;
        const DensityGrid r = spheres_to_density_grid(s, o);
        EXPECT_LE(std::max({r.size.x, r.size.y, r.size.z}), resolution) << resolution;
        EXPECT_GE(r.size.x, resolution - 1) << resolution;
    }
}

// A cloud centred on the origin straddles the lattice's lines on every axis: each side keeps two cells
// and a margin however wide the voxel, so at resolution 1 or 2 the voxel widened sixteen times (to 3.6e8
// units for an 8-unit cloud, a file vdb-import refuses). Resolutions below kMinSplatResolution are
// refused; from it on, the longest side holds the resolution with a voxel near the box's share.
TEST(VdbSplatLattice, ACloudOnTheOriginTakesTheResolutionOrIsRefused) {
    const std::vector<Sphere> s{sphere({-3.0, 0.2, -0.4}, 1.0, 1.0), sphere({3.0, -0.3, 0.5}, 1.0, 1.0)};
    SplatOptions o;
    for (int resolution : {1, 2, kMinSplatResolution - 1}) {
        o.resolution = resolution;
        EXPECT_THROW(spheres_to_density_grid(s, o), std::invalid_argument) << resolution;
    }
    for (int resolution : {kMinSplatResolution, kMinSplatResolution + 1, 12, 16, 33}) {
        o.resolution = resolution;
        const DensityGrid r = spheres_to_density_grid(s, o);
        EXPECT_LE(std::max({r.size.x, r.size.y, r.size.z}), resolution) << resolution;
        EXPECT_GE(r.size.x, resolution / 2) << resolution;
        EXPECT_LT(r.voxel_size, 2.0 * 8.0 / resolution) << resolution;  // the box is 8 long in x
    }
}

TEST(VdbSplatLattice, SpheresWithoutMassAreSkipped) {
    std::vector<Sphere> s{sphere({0, 0, 0}, 0.2, 1.0), sphere({50, 0, 0}, 0.0, 1.0), sphere({-50, 0, 0}, 3.0, 0.0)};
    const SplatGrids g = splat_spheres(s, at_voxel(0.05));
    EXPECT_EQ(g.spheres, 1u);
    EXPECT_LE(g.density.size.x, 10);
}

// --- Optical depth. -----------------------------------------------------------------------------------

// A uniform sphere of 8 voxels radius: the grid's depth through its centre is the analytic 2 r tau to within
// the blur of voxel averaging plus trilinear reconstruction, about 0.25 (voxel / r)^2 = 0.4% (measured
// 0.02% on a voxel centre, 0.27% off). Off centre the chord is steeper and the blur costs more (measured
// 0.7% at half the radius, 1.8% at three quarters); at the rim it smears depth outward.
TEST(VdbSplatOpticalDepth, UniformSphereMatchesItsAnalyticDepth) {
    const double r = 0.4, tau = 2.0, voxel = 0.05;
    for (const glm::dvec3 c : {glm::dvec3(0.0), glm::dvec3(0.0123, -0.0371, 0.0219)}) {
        const std::vector<Sphere> s{sphere(c, r, tau)};
        const DensityGrid g = spheres_to_density_grid(s, at_voxel(voxel));
        const double centre = grid_depth_z(g, 1.0, c.x, c.y);
        EXPECT_NEAR(centre / (2.0 * r * tau), 1.0, 0.005) << centre;
        for (const double b : {0.25 * r, 0.5 * r, 0.75 * r}) {
            const double analytic = spheres_depth_z(s, c.x + b, c.y);
            EXPECT_NEAR(grid_depth_z(g, 1.0, c.x + b, c.y) / analytic, 1.0, b < 0.6 * r ? 0.01 : 0.03) << b;
        }
    }
}

// --- Albedo. -------------------------------------------------------------------------------------------

TEST(VdbSplatAlbedo, ExtinctionWeightedMeanOfTheGreyAlbedo) {
    // Two coincident spheres: (0.2 * 1 + 0.7 * 3) / 4 = 0.575 in every voxel they reach; a third sphere
    // apart keeps its own grey, 0.5; voxels without density are 0.
    const std::vector<Sphere> s{sphere({0, 0, 0}, 0.3, 1.0, {0.2, 0.2, 0.2}), sphere({0, 0, 0}, 0.3, 3.0, {1.0, 0.5, 0.6}),
                                sphere({1, 0, 0}, 0.2, 1.0, {0.0, 0.5, 1.0})};
    SplatOptions o = at_voxel(0.05);
    o.albedo_grid = true;
    const SplatGrids g = splat_spheres(s, o);
    ASSERT_EQ(g.albedo.values.size(), g.density.values.size());
    EXPECT_EQ(g.albedo.name, "albedo");
    EXPECT_EQ(g.albedo.min, g.density.min);
    EXPECT_EQ(g.albedo.active_voxels, g.density.active_voxels);
    int near = 0, far = 0;
    for (int k = 0; k < g.density.size.z; ++k)
        for (int j = 0; j < g.density.size.y; ++j)
            for (int i = 0; i < g.density.size.x; ++i) {
                const float d = g.density.at(i, j, k), a = g.albedo.at(i, j, k);
                if (d == 0.0f) {
                    ASSERT_EQ(a, 0.0f);
                } else if (g.density.voxel_center(glm::dvec3(i, j, k)).x < 0.5) {
                    ASSERT_NEAR(a, 0.575, 1e-6);
                    ++near;
                } else {
                    ASSERT_NEAR(a, 0.5, 1e-6);
                    ++far;
                }
            }
    EXPECT_GT(near, 400);
    EXPECT_GT(far, 100);
    // Without the option there is no albedo grid.
    EXPECT_TRUE(splat_spheres(s, at_voxel(0.05)).albedo.values.empty());
}

// --- Round trips. --------------------------------------------------------------------------------------

TEST(VdbSplatRoundTrip, GridsSurviveEncodeAndDecode) {
    SplatOptions o;
    o.resolution = 40;
    o.albedo_grid = true;
    const SplatGrids g = splat_spheres(puff(150), o);
    const std::string bytes = encode_vdb(std::vector<DensityGrid>{g.density, g.albedo});
    const std::vector<DensityGrid> back = decode_density_grids(bytes, "splat", {"density", "albedo"});
    ASSERT_EQ(back.size(), 2u);
    const DensityGrid* original[] = {&g.density, &g.albedo};
    for (int n = 0; n < 2; ++n) {
        const DensityGrid& a = *original[n];
        const DensityGrid& b = back[n];
        EXPECT_EQ(b.voxel_size, a.voxel_size);
        EXPECT_EQ(b.origin, a.origin);
        EXPECT_EQ(b.active_voxels, a.active_voxels);
        // The decoded grid spans the active voxels only: compare by OpenVDB index.
        for (int k = 0; k < a.size.z; ++k)
            for (int j = 0; j < a.size.y; ++j)
                for (int i = 0; i < a.size.x; ++i) {
                    const glm::ivec3 q = a.min + glm::ivec3(i, j, k) - b.min;
                    const bool inside = glm::all(glm::greaterThanEqual(q, glm::ivec3(0))) && glm::all(glm::lessThan(q, b.size));
                    ASSERT_EQ(inside ? b.at(q.x, q.y, q.z) : 0.0f, a.at(i, j, k)) << n << ": " << i << " " << j << " " << k;
                }
    }
    EXPECT_EQ(back[0].mass(), g.density.mass());
}

// Export then import: the spheres vdb-import makes of the exported grid carry the original spheres'
// extinction mass (splatting is exact, import keeps the grid's), and their optical depth along parallel
// rays through the puff matches the original spheres' to within the splat's own error (the grid against the
// spheres, measured 3.3% RMS at 32 voxels across, the blur of a voxel on spheres of 1-5 voxels) plus the
// tolerance import is asked for (0.1, which it measures against the grid over its own views, so allow it a
// fifth more over these rays): measured 12.5% RMS.
class VdbSplatImport : public ScratchDir {};

TEST_F(VdbSplatImport, ExportThenImportKeepsMassAndOpticalDepth) {
    const std::vector<Sphere> original = puff(300);
    SplatOptions o;
    o.resolution = 32;  // import's time grows with the voxels; 32 keeps this test near a second
    o.extinction_scale = 4.0;
    const DensityGrid g = spheres_to_density_grid(original, o);
    write_bytes(dir_ / "frame.vdb", encode_vdb(g));
    SphereCloudOptions io;
    io.tolerance = 0.1;
    io.extinction_scale = 4.0;
    const VdbImport im = import_vdb(dir_ / "frame.vdb", "density", io);
    const double mass = spheres_extinction_mass(original);
    EXPECT_NEAR(spheres_extinction_mass(im.scene.spheres), mass, 1e-6 * mass);

    // Rays on a 0.013 lattice (not a multiple of the voxel, 0.044) over the whole puff.
    double grid_d2 = 0.0, import_d2 = 0.0, ref2 = 0.0;
    for (double y = -0.8; y <= 0.8; y += 0.013)
        for (double x = -0.8; x <= 0.8; x += 0.013) {
            const double ref = spheres_depth_z(original, x, y);
            const double grid = grid_depth_z(g, 4.0, x, y) - ref;
            const double imported = spheres_depth_z(im.scene.spheres, x, y) - ref;
            grid_d2 += grid * grid;
            import_d2 += imported * imported;
            ref2 += ref * ref;
        }
    const double grid_rms = std::sqrt(grid_d2 / ref2), import_rms = std::sqrt(import_d2 / ref2);
    std::printf("optical depth against the original spheres: grid %.2f%% RMS, imported spheres %.2f%% RMS (%zu spheres)\n",
                100.0 * grid_rms, 100.0 * import_rms, im.scene.spheres.size());
    EXPECT_LT(grid_rms, 0.06);
    EXPECT_LT(import_rms, grid_rms + 1.2 * io.tolerance);
}

// --- Refusals. -----------------------------------------------------------------------------------------

TEST(VdbSplatErrors, BadSpheresAreNamed) {
    const Sphere good = sphere({0, 0, 0}, 0.2, 1.0);
    const double nan = std::nan("");
    std::vector<Sphere> s{good, good};
    s[1].radius = nan;
    EXPECT_NE(splat_error(s, {}).find("sphere[1].radius"), std::string::npos);
    s[1] = good;
    s[1].extinction = -2.0;
    EXPECT_NE(splat_error(s, {}).find("sphere[1].extinction"), std::string::npos);
    s[1] = good;
    s[1].center.y = nan;
    EXPECT_NE(splat_error(s, {}).find("sphere[1].center"), std::string::npos);
    s[1] = good;
    s[1].albedo.z = INFINITY;
    EXPECT_NE(splat_error(s, {}).find("sphere[1].albedo"), std::string::npos);
    EXPECT_NE(splat_error({}, {}).find("no spheres"), std::string::npos);
    EXPECT_NE(splat_error({sphere({0, 0, 0}, 0.0, 1.0)}, {}).find("nothing"), std::string::npos);
}

TEST(VdbSplatErrors, BadOptionsAreNamed) {
    const std::vector<Sphere> s{sphere({0, 0, 0}, 0.2, 1.0)};
    EXPECT_NE(splat_error(s, at_voxel(-0.1)).find("voxel size"), std::string::npos);
    EXPECT_NE(splat_error(s, at_voxel(std::nan(""))).find("voxel size"), std::string::npos);
    SplatOptions o;
    o.resolution = 0;
    EXPECT_NE(splat_error(s, o).find("resolution"), std::string::npos);
    o = {};
    o.extinction_scale = 0.0;
    EXPECT_NE(splat_error(s, o).find("extinction scale"), std::string::npos);
    o.extinction_scale = std::nan("");
    EXPECT_NE(splat_error(s, o).find("extinction scale"), std::string::npos);
}

TEST(VdbSplatErrors, VoxelsThatLoseTheDensityAreRefused) {
    // Issue 14: --voxel-size 1e30 wrote an empty grid and exited 0. Out of the range vdb-import reads, refused
    // by range; inside it but so coarse that the density underflows a float, refused by the mass it lost.
    const std::vector<Sphere> s{sphere({0, 0, 0}, 0.2, 1.0)};
    EXPECT_NE(splat_error(s, at_voxel(1e30)).find("outside"), std::string::npos) << splat_error(s, at_voxel(1e30));
    const std::vector<Sphere> faint{sphere({0, 0, 0}, 1e-3, 1e-20)};
    const std::string e = splat_error(faint, at_voxel(1e6));
    EXPECT_NE(e.find("does not survive as floats"), std::string::npos) << e;
}

TEST(VdbSplatErrors, AbsurdGridsAreRefusedBeforeAllocating) {
    // 10 units at voxel 1e-3: 10^12 voxels. Refused at once, naming the count and a voxel size that fits.
    const std::vector<Sphere> s{sphere({0, 0, 0}, 5.0, 1.0)};
    const std::string e = splat_error(s, at_voxel(1e-3));
    EXPECT_NE(e.find("10001 x 10001 x 10001"), std::string::npos) << e;
    EXPECT_NE(e.find("voxels"), std::string::npos) << e;
    EXPECT_NE(e.find("larger voxel size"), std::string::npos) << e;
    SplatOptions o;
    o.resolution = 2000;
    EXPECT_NE(splat_error(s, o).find("2^30"), std::string::npos);
    // The suggested size would fit (checked by arithmetic: allocating 2^30 voxels here would take 12 GB).
    const std::size_t about = e.find("about ");
    ASSERT_NE(about, std::string::npos) << e;
    const double fits = std::stod(e.substr(about + 6));
    EXPECT_LT(std::pow(10.0 / fits + 2.0, 3), double(kMaxSplatVoxels)) << fits;
    EXPECT_GT(std::pow(10.0 / fits + 2.0, 3), 0.5 * double(kMaxSplatVoxels)) << fits;
}

}  // namespace
}  // namespace brume
