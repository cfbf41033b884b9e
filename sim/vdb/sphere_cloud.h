// A density grid as a cloud of spheres (issue 5): an adaptive octree over the grid's voxels in which a cell
// becomes one sphere once its densities are near-uniform, so uniform regions cost one sphere, not one per
// voxel. Each sphere has its cell's volume and mean density, so the total extinction mass
// (sum of extinction * volume) equals the grid's exactly. What it does not keep is the cell's shape: a
// sphere of a cube's volume reaches past the cube's faces and misses its corners, and
// optical_depth_error.h measures what that costs along camera rays.
#pragma once

#include "sim/scene.h"
#include "sim/density_grid.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace brume {

struct SphereCloudOptions {
    // A cell is one sphere when its densities spread (max - min) by at most tolerance * the grid's largest
    // density; in [0, 1]. Relative to the grid, not the cell, so faint fringes, which matter little to
    // optical depth, merge as readily as the dense core. 0 splits every non-constant cell down to voxels;
    // 1 makes the whole grid one sphere.
    double tolerance = 0.05;
    // When > 0: the tolerance is coarsened (bisection between `tolerance` and 1) until at most this many
    // spheres remain; the result says which tolerance it used.
    std::size_t max_spheres = 0;
    double extinction_scale = 1.0;  // sphere extinction = mean density * extinction_scale
    glm::dvec3 albedo{1.0};
};

struct SphereCloud {
    std::vector<Sphere> spheres;
    double tolerance = 0.0;  // the tolerance that produced them
};

// Throws std::invalid_argument for options out of range (tolerance outside [0, 1], non-positive or
// non-finite extinction_scale, albedo outside [0, 1]). An all-zero grid gives no spheres.
SphereCloud grid_to_spheres(const DensityGrid& grid, const SphereCloudOptions& options);

}  // namespace brume
