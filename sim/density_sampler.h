// Points distributed in proportion to a density grid's trilinear field (sim/density_grid.h), placed in
// the scene by a VolumeTransform: where a density-seeded emitter (EmitterShape::Density) gives birth.
//
// Exact, not approximate. The trilinear field between voxel centres is the sum over voxels of
// value * T(x) T(y) T(z), T the tent 1 - |t| over one voxel either side of the voxel's centre, and each
// such product integrates to one voxel volume. So the field, normalised, is a mixture: pick a voxel with
// probability value / sum of values, then offset each axis independently by a tent-distributed amount.
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace brume {

class DensitySampler {
public:
    // Throws std::invalid_argument when the grid holds no positive density (nothing to sample), has more
    // voxels than 32-bit indices reach, or the transform is unusable (volume_transform_problem).
    DensitySampler(DensityGrid grid, const VolumeTransform& transform = {});

    // A world position from four uniforms in [0, 1): u0 picks the voxel (binary search of the CDF),
    // u1, u2, u3 the tent offsets along x, y, z. A pure function of its arguments.
    glm::dvec3 sample(double u0, double u1, double u2, double u3) const;

    const DensityGrid& grid() const { return grid_; }
    const VolumeTransform& transform() const { return transform_; }
    // The integral of the field in the grid's own units (DensityGrid::mass, before the transform's scale).
    double mass() const;

private:
    DensityGrid grid_;
    VolumeTransform transform_;
    // Only voxels with positive values, each with the running sum of values up to and including it:
    // zero voxels (most of a sparse cloud) cost nothing and can never be picked.
    std::vector<std::uint32_t> voxels_;  // DensityGrid::offset of each
    std::vector<double> cdf_;            // ascending; cdf_.back() is the sum of every value
};

// The inverse CDF of the tent density 1 - |t| on [-1, 1]: a tent-distributed value from u in [0, 1).
double tent_offset(double u);

}  // namespace brume
