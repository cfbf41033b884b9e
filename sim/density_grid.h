// A scalar density field on a uniform voxel grid, Brume's side of an OpenVDB float grid: dense over the
// active bounding box, no OpenVDB types, so conversion and measurement compile without OpenVDB.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace brume {

// Voxel (i, j, k) (OpenVDB index coordinates) has its centre at origin + voxel_size * (i, j, k), as in
// OpenVDB. The field between voxel centres is trilinear; voxels outside the box are 0.
struct DensityGrid {
    std::string name = "density";
    glm::dvec3 origin{0.0};  // world position of the centre of voxel (0, 0, 0)
    double voxel_size = 1.0;
    glm::ivec3 min{0};            // index of values[0]
    glm::ivec3 size{0};           // voxels per axis
    std::vector<float> values;    // x fastest, then y, then z; every value finite and >= 0
    std::uint64_t active_voxels = 0;  // as OpenVDB counts them (tiles included); the others are 0

    std::size_t voxel_count() const { return values.size(); }
    // (i, j, k) relative to min, each in [0, size).
    std::size_t offset(int i, int j, int k) const {
        return (std::size_t(k) * std::size_t(size.y) + std::size_t(j)) * std::size_t(size.x) + std::size_t(i);
    }
    float at(int i, int j, int k) const { return values[offset(i, j, k)]; }

    // World position of the centre of voxel min + local.
    glm::dvec3 voxel_center(const glm::dvec3& local) const;
    // The box the voxels fill (each voxel a cube of side voxel_size around its centre).
    glm::dvec3 world_min() const;
    glm::dvec3 world_max() const;
    // Where the trilinear field can be non-zero: the voxel box grown by half a voxel on every side.
    glm::dvec3 support_min() const;
    glm::dvec3 support_max() const;

    // Trilinear interpolation between voxel centres, 0 beyond the support.
    double sample(const glm::dvec3& world) const;
    // Integral of the field over space: sum of values * voxel volume (each trilinear hat integrates to
    // one voxel volume).
    double mass() const;
};

}  // namespace brume
