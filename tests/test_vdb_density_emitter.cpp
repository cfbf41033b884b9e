// Density-seeded emitters end to end (sim/vdb/emitter_densities.h): a preset names a grid, the grid is
// read and sampled, and the simulator's births sit inside it, centred where its density is; a grid
// that cannot be read is a VdbError naming the emitter.
#include "sim/density_sampler.h"
#include "sim/preset_file.h"
#include "sim/simulator.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/emitter_densities.h"
#include "sim/vdb/vdb_file.h"
#include "sim/volume_transform.h"

#include "tests/vdb_test_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

namespace brume {
namespace {

using namespace vdb_test;

// A point emitter first, so the density emitter's index in messages is 1, not a default 0.
std::string preset_text(const std::string& density_lines) {
    return "[timeline]\nfps = 24\nduration = 1\nseed = 5\nmax_particles = 10000\n\n"
           "[[emitter]]\nname = \"spark\"\nbursts = [{ time = 0.5, count = 1 }]\n\n"
           "[[emitter]]\nname = \"seeded cloud\"\nshape = \"density\"\n" +
           density_lines +
           "\nbursts = [{ time = 0.0, count = 6000 }]\nspeed = 0\nlifetime = 10\nparticle_radius = 0.02\n";
}

// The centroid of the field: voxel centres weighted by value (each voxel's tent is symmetric about it).
glm::dvec3 centroid(const DensityGrid& g) {
    double weight = 0.0;
    glm::dvec3 sum(0.0);
    for (int k = 0; k < g.size.z; ++k)
        for (int j = 0; j < g.size.y; ++j)
            for (int i = 0; i < g.size.x; ++i) {
                weight += g.at(i, j, k);
                sum += double(g.at(i, j, k)) * g.voxel_center(glm::dvec3(i, j, k));
            }
    return sum / weight;
}

std::string file_text_of(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The message of the VdbError load_emitter_densities throws for `p`.
std::string load_error(Preset p) {
    try {
        load_emitter_densities(p);
    } catch (const VdbError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no VdbError";
    return "";
}

TEST(VdbDensityEmitter, BirthsFillTheBuiltInCloud) {
    Preset p = parse_preset_toml(
        preset_text("file = \"builtin:cloud:32\"\ntranslate = [0.5, 2.0, -1.0]\nscale = 1.5\nrotate = [0, 30, 0]"),
        "seeded.toml");
    load_emitter_densities(p);
    ASSERT_NE(p.emitters[1].density, nullptr);
    EXPECT_EQ(p.emitters[0].density, nullptr) << "only density emitters get a grid";
    const DensitySampler& sampler = *p.emitters[1].density;
    const DensityGrid grid = read_density_source(DensitySource{"builtin:cloud:32", "", "density"});
    EXPECT_EQ(sampler.grid().values, grid.values);
    const VolumeTransform& t = p.emitters[1].density_transform;

    Simulator sim(p);
    sim.advance_to_frame(3);  // still, and long-lived: births stay where they were made
    const Particles& particles = sim.particles();
    ASSERT_EQ(particles.size(), 6000u);
    const glm::dvec3 lo = grid.support_min(), hi = grid.support_max();
    glm::dvec3 sum(0.0), sum_sq(0.0);
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const glm::dvec3 q = world_to_volume(t, glm::dvec3(particles.x[i], particles.y[i], particles.z[i]));
        for (int a = 0; a < 3; ++a) {
            ASSERT_GE(q[a], lo[a] - 1e-5) << "particle " << i << " axis " << a;
            ASSERT_LE(q[a], hi[a] + 1e-5) << "particle " << i << " axis " << a;
        }
        sum += q;
        sum_sq += q * q;
    }
    const double n = double(particles.size());
    const glm::dvec3 mean = sum / n, variance = sum_sq / n - mean * mean;
    const glm::dvec3 expected = centroid(grid);
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mean[a], expected[a], 5.0 * std::sqrt(variance[a] / n)) << "axis " << a;
}

TEST(VdbDensityEmitter, ParticlesLieWhereTheFieldIsPositive) {
    // Every birth from a grid with holes sits where the trilinear field is positive.
    Preset p = parse_preset_toml(preset_text("file = \"builtin:cloud:16\""), "seeded.toml");
    load_emitter_densities(p);
    const DensityGrid& grid = p.emitters[1].density->grid();
    Simulator sim(p);
    const Particles& particles = sim.particles();
    ASSERT_EQ(particles.size(), 6000u);
    int outside = 0;
    for (std::size_t i = 0; i < particles.size(); ++i)
        outside += !(grid.sample(glm::dvec3(particles.x[i], particles.y[i], particles.z[i])) > 0.0);
    // A float position can land a rounding error outside the edge of the support: a handful at most.
    EXPECT_LE(outside, 3);
}

class VdbDensityEmitterFiles : public ScratchDir {};

TEST_F(VdbDensityEmitterFiles, ARelativeFileIsReadBesideThePreset) {
    fs::create_directories(dir_ / "grids");
    const DensityGrid cloud = noise_cloud(16);
    write_bytes(dir_ / "grids" / "lump.vdb", encode_vdb(cloud));
    const fs::path path = dir_ / "lumpy.toml";
    std::ofstream(path) << preset_text("file = \"grids/lump.vdb\"");
    ASSERT_NE(fs::current_path(), dir_);
    Preset p = load_preset_file(path);
    load_emitter_densities(p);
    EXPECT_EQ(p.emitters[1].density->grid().active_voxels, cloud.active_voxels);
    EXPECT_NEAR(p.emitters[1].density->mass(), cloud.mass(), 1e-9 * cloud.mass());

    // Parsed as text, the same preset looks in the working directory, and says which emitter failed.
    const std::string what = load_error(parse_preset_toml(file_text_of(path), "lumpy.toml"));
    EXPECT_EQ(what.rfind("lumpy.toml:11: emitter[1] (\"seeded cloud\"): grids/lump.vdb", 0), 0u) << what;
}

// Each message starts with the emitter's table, FILE:LINE first, as a [[vdb]] volume's and the reader's do.
TEST_F(VdbDensityEmitterFiles, UnreadableGridsNameTheEmitter) {
    const std::string missing = load_error(parse_preset_toml(preset_text("file = \"no_such_cloud.vdb\""), "p.toml"));
    EXPECT_EQ(missing.rfind("p.toml:11: emitter[1] (\"seeded cloud\"): ", 0), 0u) << missing;
    EXPECT_NE(missing.find("no_such_cloud.vdb"), std::string::npos) << missing;

    const std::string wrong_grid =
        load_error(parse_preset_toml(preset_text("file = \"builtin:cloud:16\"\ngrid = \"smoke\""), "p.toml"));
    EXPECT_EQ(wrong_grid.rfind("p.toml:11: emitter[1] (\"seeded cloud\"): builtin:cloud:16", 0), 0u) << wrong_grid;
    EXPECT_NE(wrong_grid.find("\"smoke\""), std::string::npos) << wrong_grid;

    const std::string unknown = load_error(parse_preset_toml(preset_text("file = \"builtin:nimbus\""), "p.toml"));
    EXPECT_EQ(unknown.rfind("p.toml:11: emitter[1] (\"seeded cloud\"): ", 0), 0u) << unknown;
    EXPECT_NE(unknown.find("nimbus"), std::string::npos) << unknown;

    // A grid of zeros has nothing to seed from (OpenVDB keeps no active voxel of it).
    DensityGrid zeros = uniform_box();
    std::fill(zeros.values.begin(), zeros.values.end(), 0.0f);
    zeros.active_voxels = 0;
    write_bytes(dir_ / "empty.vdb", encode_vdb(zeros));
    const std::string empty =
        load_error(parse_preset_toml(preset_text("file = \"" + (dir_ / "empty.vdb").string() + "\""), "p.toml"));
    EXPECT_EQ(empty.rfind("p.toml:11: emitter[1] (\"seeded cloud\"): ", 0), 0u) << empty;
    EXPECT_NE(empty.find("empty.vdb"), std::string::npos) << empty;
}

}  // namespace
}  // namespace brume
