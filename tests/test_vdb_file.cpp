// Reading .vdb files (sim/vdb/vdb_file.h): grids written with OpenVDB's own API read back exactly, and
// every bad input is refused with a message naming the file and the problem.
#include "sim/vdb/vdb_file.h"

#include "tests/vdb_test_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sys/stat.h>
#include <iostream>
#include <sstream>

namespace brume {
namespace {

using namespace vdb_test;

class VdbFile : public ScratchDir {
protected:
    // The message of the VdbError that reading `grid` from `path` throws; fails the test when none is thrown.
    std::string read_error(const fs::path& path, const std::string& grid = "density") {
        try {
            read_density_grid(path, grid);
        } catch (const VdbError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
            return e.what();
        }
        ADD_FAILURE() << "no VdbError for " << path;
        return "";
    }
    fs::path write(const std::string& name, const std::string& bytes) {
        write_bytes(dir_ / name, bytes);
        return dir_ / name;
    }
};

TEST_F(VdbFile, BoxReadsBackWithItsTransformAndValues) {
    const DensityGrid box = uniform_box();
    const DensityGrid g = read_density_grid(write("box.vdb", encode_vdb(box)));
    EXPECT_EQ(g.name, "density");
    EXPECT_EQ(g.min, box.min);
    EXPECT_EQ(g.size, box.size);
    EXPECT_EQ(g.origin, box.origin);
    EXPECT_EQ(g.voxel_size, box.voxel_size);
    EXPECT_EQ(g.active_voxels, box.values.size());
    EXPECT_EQ(g.values, box.values);
}

TEST_F(VdbFile, NoiseCloudReadsBackVoxelForVoxel) {
    // Asymmetric in x, y and z, so a transposed copy or a wrong offset shows.
    const DensityGrid cloud = noise_cloud(32);
    const DensityGrid g = read_density_grid(write("cloud.vdb", encode_vdb(cloud)));
    EXPECT_EQ(g.active_voxels, cloud.active_voxels);
    for (int k = 0; k < cloud.size.z; ++k)
        for (int j = 0; j < cloud.size.y; ++j)
            for (int i = 0; i < cloud.size.x; ++i) {
                const glm::dvec3 p = cloud.voxel_center(glm::dvec3(i, j, k));
                ASSERT_NEAR(g.sample(p), cloud.at(i, j, k), 1e-6) << i << " " << j << " " << k;
            }
    EXPECT_NEAR(g.mass(), cloud.mass(), 1e-9 * cloud.mass());
}

TEST_F(VdbFile, FogSphereFromALevelSetReadsWithItsTiles) {
    // Radius 1 at voxel size 1/32: a 64^3 fog sphere whose interior OpenVDB stores as constant tiles.
    const DensityGrid g = read_density_grid(write("fog.vdb", encode_fog_sphere_vdb(1.0, {0.5, 0.0, -0.5}, 1.0 / 32.0)));
    EXPECT_EQ(g.voxel_size, 1.0 / 32.0);
    EXPECT_EQ(g.size, glm::ivec3(63));
    EXPECT_GT(g.active_voxels, 130000u);
    EXPECT_EQ(g.sample({0.5, 0.0, -0.5}), 1.0);
    EXPECT_EQ(g.sample({0.5, 0.0, 0.6}), 0.0);
    // Density falls from 1 to 0 over three voxels inside the surface: a little less than the unit ball.
    EXPECT_GT(g.mass(), 0.8 * 4.0 / 3.0 * M_PI);
    EXPECT_LT(g.mass(), 4.0 / 3.0 * M_PI);
}

TEST_F(VdbFile, ReadsTheGridItIsAskedFor) {
    const fs::path path = write("smoke.vdb", encode_fog_sphere_vdb(1.0, {0, 0, 0}, 0.125, "smoke"));
    EXPECT_EQ(read_density_grid(path, "smoke").name, "smoke");
}

TEST_F(VdbFile, ListsGrids) {
    const auto infos = list_vdb_grids(write("fog.vdb", encode_fog_sphere_vdb(1.0, {0, 0, 0}, 0.125)));
    ASSERT_EQ(infos.size(), 1u);
    EXPECT_EQ(infos[0].name, "density");
    EXPECT_EQ(infos[0].value_type, "float");
    EXPECT_EQ(infos[0].grid_class, "Fog Volume");
    EXPECT_GT(infos[0].active_voxels, 0u);
    EXPECT_EQ(infos[0].bbox_min, glm::ivec3(-7));
    EXPECT_EQ(infos[0].bbox_max, glm::ivec3(7));
    EXPECT_EQ(infos[0].voxel_size, glm::dvec3(0.125));
}

// The one list of built-in names that vdb-sample, bench vdb and scenes' "builtin:NAME" all check against.
TEST(SampleVolumes, EveryListedNameIsKnownAndMakesAVolume) {
    const std::string names = sample_volume_names();
    for (const SampleVolumeInfo& s : sample_volumes()) {
        EXPECT_TRUE(is_sample_volume(s.name)) << s.name;
        EXPECT_NE(names.find(s.name), std::string::npos) << names;
        EXPECT_FALSE(encode_sample_volume_vdb(s.name, kMinSampleResolution).empty()) << s.name;
    }
    EXPECT_EQ(names, "cloud, fog-sphere, sheet");
    for (const char* unknown : {"", "nebula", "Cloud", "cloud "}) EXPECT_FALSE(is_sample_volume(unknown)) << unknown;
    try {
        encode_sample_volume_vdb("nebula", 16);
        ADD_FAILURE() << "no VdbError for builtin:nebula";
    } catch (const VdbError& e) {
        EXPECT_NE(std::string(e.what()).find("(there are: " + names + ")"), std::string::npos) << e.what();
    }
}

TEST_F(VdbFile, MissingFileIsRefused) {
    const std::string msg = read_error(dir_ / "nowhere.vdb");
    EXPECT_NE(msg.find("cannot open: No such file or directory"), std::string::npos) << msg;
    EXPECT_THROW(list_vdb_grids(dir_ / "nowhere.vdb"), VdbError);
}

TEST_F(VdbFile, DirectoryIsRefused) {
    EXPECT_NE(read_error(dir_).find("is a directory"), std::string::npos);
}

// A pipe may never end (fed from /dev/zero) and has no size to check: refused by name before it is opened,
// which would also block until a writer came.
TEST_F(VdbFile, PipeIsRefusedBeforeAnyRead) {
    const fs::path fifo = dir_ / "volume.vdb";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const std::string msg = read_error(fifo);
    EXPECT_NE(msg.find("is a pipe (FIFO), not a VDB file"), std::string::npos) << msg;
}

TEST_F(VdbFile, GarbageAndEmptyFilesAreNotVdbFiles) {
    const std::string garbage = read_error(write("garbage.vdb", std::string(4096, 'x') + "not a volume"));
    EXPECT_NE(garbage.find("not a VDB file"), std::string::npos) << garbage;
    const std::string tiny = read_error(write("tiny.vdb", "junk"));
    EXPECT_NE(tiny.find("not a VDB file"), std::string::npos) << tiny;
    const std::string empty = read_error(write("empty.vdb", ""));
    EXPECT_NE(empty.find("empty file, not a VDB file"), std::string::npos) << empty;
}

TEST_F(VdbFile, TruncatedFilesAreRefusedWhereverTheyEnd) {
    const std::string whole = encode_fog_sphere_vdb(1.0, {0, 0, 0}, 1.0 / 16.0);
    for (const double fraction : {0.001, 0.01, 0.1, 0.5, 0.9, 0.999}) {
        const std::size_t keep = std::max<std::size_t>(1, std::size_t(double(whole.size()) * fraction));
        const fs::path path = write("cut.vdb", whole.substr(0, keep));
        const std::string msg = read_error(path);
        EXPECT_NE(msg.find("truncated or corrupted"), std::string::npos) << keep << " bytes: " << msg;
        EXPECT_THROW(list_vdb_grids(path), VdbError);
    }
}

// OpenVDB reads past some corruption with a warning on std::cerr and a tree that may be wrong (a
// corrupted buffer count: "multi-buffer trees are no longer supported"), and warns on std::cout before
// some errors. Every byte of a small file set to 2 (a buffer count of 2, among others) is either read or
// refused with a VdbError of one line, and nothing reaches std::cout or std::cerr.
TEST_F(VdbFile, CorruptionOpenVdbOnlyWarnsAboutIsRefusedWithOneLine) {
    DensityGrid grid;
    grid.size = {3, 2, 2};
    grid.values.assign(12, 0.5f);
    const std::string whole = encode_vdb(grid);
    int warned = 0, refused = 0;
    // From byte 512 on: the grid's tree, whose buffer count sits near byte 650. The bytes before it are the
    // header, metadata and transform, where a length corrupted to millions makes OpenVDB allocate and zero
    // that much before it finds the data short (up to 3 s each, refused as truncated all the same).
    ASSERT_GT(whole.size(), 1024u);
    for (std::size_t at = 512; at < whole.size(); ++at) {
        for (const unsigned char value : {0x02}) {
            if (static_cast<unsigned char>(whole[at]) == value) continue;
            std::string bytes = whole;
            bytes[at] = static_cast<char>(value);
            std::ostringstream captured;
            std::streambuf* const saved_out = std::cout.rdbuf(captured.rdbuf());
            std::streambuf* const saved_err = std::cerr.rdbuf(captured.rdbuf());
            std::string message;
            try {
                (void)decode_density_grids(bytes, "flipped.vdb", {"density"});
            } catch (const VdbError& e) {
                message = e.what();
            } catch (const std::exception& e) {
                message = std::string("not a VdbError: ") + e.what();
            }
            std::cout.rdbuf(saved_out);
            std::cerr.rdbuf(saved_err);
            EXPECT_EQ(captured.str(), "") << "byte " << at << " = " << int(value);
            if (message.empty()) continue;
            ++refused;
            EXPECT_EQ(message.rfind("flipped.vdb: ", 0), 0u) << "byte " << at << ": " << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << "byte " << at << ": " << message;
            if (message.find("multi-buffer trees") != std::string::npos) ++warned;
        }
    }
    EXPECT_GT(refused, 0);
    EXPECT_GT(warned, 0) << "no corruption reached OpenVDB's buffer-count warning: the case is no longer covered";
}

TEST_F(VdbFile, MissingGridNamesTheOnesThereAre) {
    const fs::path path = write("smoke.vdb", encode_fog_sphere_vdb(1.0, {0, 0, 0}, 0.125, "smoke"));
    const std::string msg = read_error(path, "density");
    EXPECT_NE(msg.find("no grid named \"density\" (grids: \"smoke\")"), std::string::npos) << msg;
}

TEST_F(VdbFile, WrongValueTypeIsRefused) {
    const std::string msg = read_error(write("vec.vdb", encode_refused_vdb_sample(RefusedVdbSample::vector_grid)));
    EXPECT_NE(msg.find("grid \"density\" holds vec3s values; Brume reads float density grids"), std::string::npos) << msg;
}

TEST_F(VdbFile, EmptyGridIsRefused) {
    DensityGrid zeros = uniform_box();
    std::fill(zeros.values.begin(), zeros.values.end(), 0.0f);
    const std::string msg = read_error(write("zeros.vdb", encode_vdb(zeros)));
    EXPECT_NE(msg.find("grid \"density\" is empty (no active voxels)"), std::string::npos) << msg;
}

TEST_F(VdbFile, NegativeDensityIsRefused) {
    DensityGrid box = uniform_box();
    box.values[box.offset(1, 2, 3)] = -0.25f;
    const std::string msg = read_error(write("negative.vdb", encode_vdb(box)));
    EXPECT_NE(msg.find("has density -0.25 at voxel (4, -3, 10); densities must be finite and non-negative"),
              std::string::npos)
        << msg;
}

TEST_F(VdbFile, OnlyUniformScaleTransformsAreRead) {
    for (const auto kind : {RefusedVdbSample::nonuniform_scale, RefusedVdbSample::rotated}) {
        const std::string msg = read_error(write("xf.vdb", encode_refused_vdb_sample(kind)));
        EXPECT_NE(msg.find("Brume reads only uniform-scale linear transforms"), std::string::npos) << msg;
    }
    const std::string msg = read_error(write("xf.vdb", encode_refused_vdb_sample(RefusedVdbSample::nonuniform_scale)));
    EXPECT_NE(msg.find("voxels of 1 x 2 x 1 scene units"), std::string::npos) << msg;
}

TEST_F(VdbFile, SparseVoxelsFarApartAreRefusedByName) {
    // Issue 14: two voxels 2e8 apart made a dense copy of 2e8 voxels and then std::bad_alloc.
    const std::string msg = read_error(write("far.vdb", encode_refused_vdb_sample(RefusedVdbSample::far_apart)));
    EXPECT_EQ(msg.find("bad_alloc"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("out of host memory"), std::string::npos) << msg;
    EXPECT_NE(msg.find("reaches 2e+08 from the origin"), std::string::npos) << msg;
}

TEST_F(VdbFile, TransformsOutsideTheRenderableRangeAreRefused) {
    // Issue 14: a voxel of 1e20 rendered every pixel NaN (squared distances overflow float) and exited 0.
    // The range is checked where the transform enters, naming the voxel size and the reach.
    DensityGrid box = uniform_box();
    box.voxel_size = 1e20;
    std::string msg = read_error(write("huge.vdb", encode_vdb(box)));
    EXPECT_NE(msg.find("has voxels of 1e+20 scene units"), std::string::npos) << msg;
    EXPECT_NE(msg.find("within 1e+07 of the origin"), std::string::npos) << msg;
    EXPECT_NE(msg.find("voxels of at least 1e-06"), std::string::npos) << msg;
    // Sensible voxels far out: the reach alone is refused.
    box = uniform_box();
    box.origin = {3e7, 0.0, 0.0};
    msg = read_error(write("far.vdb", encode_vdb(box)));
    EXPECT_NE(msg.find("reaches 3"), std::string::npos) << msg;
    // At the edge of the range, still read.
    box = uniform_box();
    box.origin = {9e6, 0.0, 0.0};
    write("near.vdb", encode_vdb(box));
    EXPECT_NO_THROW(read_density_grid(dir_ / "near.vdb"));
}

}  // namespace
}  // namespace brume
