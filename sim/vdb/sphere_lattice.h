// A density grid resampled onto a regular lattice of spheres: cells of `spacing` voxels on a side, each
// non-empty cell one sphere at its centre holding the exact integral of the trilinear field over the
// cell. A regular lattice of overlapping spheres (sphere_scale 2) has almost no ripple (sphere_cloud.h),
// and unlike an octree it has no seams where large cells meet small ones, so for a smooth field it is
// often the fewest spheres for a given error; grid_to_spheres tries both.
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"

#include <vector>

namespace brume {

struct SphereCloudOptions;

// spacing in voxels, > 1 (at 1, grid_to_spheres_at with cells of one voxel is the same lattice without
// resampling). The cells cover the field's whole support, so the spheres' total extinction mass equals
// the grid's (to rounding).
std::vector<Sphere> grid_to_lattice_spheres(const DensityGrid& grid, const SphereCloudOptions& options, double spacing);

}  // namespace brume
