// Sample density grids for the test_vdb_* suites, made at test time (the project has no internet):
// analytic DensityGrids that encode_vdb turns into files, and a scratch directory per test.
#pragma once

#include "sim/density_grid.h"
#include "tests/scratch_dir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace brume::vdb_test {

namespace fs = std::filesystem;

// size^3 voxels of side `voxel_size`, centred on the world origin, density f(world position of the voxel).
inline DensityGrid analytic_grid(int size, double voxel_size, const std::function<double(glm::dvec3)>& f) {
    DensityGrid g;
    g.voxel_size = voxel_size;
    g.min = glm::ivec3(-size / 2);
    g.size = glm::ivec3(size);
    g.values.resize(std::size_t(size) * size * size);
    for (int k = 0; k < size; ++k)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const float v = float(f(g.voxel_center(glm::dvec3(i, j, k))));
                g.values[g.offset(i, j, k)] = v;
                if (v != 0.0f) ++g.active_voxels;
            }
    return g;
}

// Density 1 inside a ball of radius 0.9 with a hard edge: the uniform-ball case.
inline DensityGrid uniform_ball(int size) {
    return analytic_grid(size, 2.0 / size, [](glm::dvec3 p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z) < 0.9 ? 1.0 : 0.0; });
}

// A smooth lumpy cloud: a radial falloff modulated by products of sines, zero beyond radius 0.95.
inline DensityGrid noise_cloud(int size) {
    return analytic_grid(size, 2.0 / size, [](glm::dvec3 p) {
        const double r = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        const double falloff = std::max(0.0, 1.0 - r / 0.95);
        return falloff * falloff * (0.6 + 0.4 * std::sin(5.0 * p.x + 1.0) * std::sin(4.0 * p.y + 2.0) * std::sin(6.0 * p.z + 0.5));
    });
}

// A 12 x 8 x 20 box of density 0.5, off the origin, its first voxel at index (3, -5, 7).
inline DensityGrid uniform_box() {
    DensityGrid g;
    g.origin = {0.25, -1.0, 2.0};
    g.voxel_size = 0.0625;
    g.min = {3, -5, 7};
    g.size = {12, 8, 20};
    g.values.assign(std::size_t(12) * 8 * 20, 0.5f);
    g.active_voxels = g.values.size();
    return g;
}

inline void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
}

// A fresh directory per test, removed afterwards.
using ScratchDir = brume::testing::ScratchDir;

}  // namespace brume::vdb_test
