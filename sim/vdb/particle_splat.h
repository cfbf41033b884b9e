// Spheres back to a density grid (`brume vdb-export`; docs/vdb.md, "Export"): the inverse of
// sphere_cloud.h, so a simulated frame opens in other VFX tools. Each voxel holds the spheres'
// extinction averaged over the voxel's cube, divided by extinction_scale, so the grid's trilinear field
// (density_grid.h) carries the spheres' extinction mass, sum of extinction * 4/3 pi r^3, to rounding
// (about 1e-9 relative).
//
// How. A sphere's share of a voxel is integrated exactly along x (the chord of each column) and by
// midpoint subsamples across y and z (4 x 4 per voxel face, more for spheres of a voxel or two), so voxels
// wholly inside get exactly 1 and those wholly outside 0. The shares are then rescaled so the sphere
// deposits exactly its own mass: subsampling moves mass between a sphere's edge voxels, never creates or
// loses any. A sphere under a voxel across cannot be resolved and deposits its mass as trilinear weights
// around its centre instead (the same hat the grid's field uses), so it neither snaps to one voxel nor
// vanishes. Accumulation is in double; the float values carry their rounding on to the next voxel, so
// the float grid's sum is the double sum.
//
// The lattice is anchored at the world origin (voxel (0, 0, 0) centred on it, a pure-scale OpenVDB
// transform) so frames exported at one voxel size share their voxels; only coordinates beyond 2^30 voxels
// move the origin to the spheres' corner.
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace brume {

// Beyond this a grid is refused (4 bytes a voxel in the grid, 8 more while splatting, as much again for
// the albedo grid).
inline constexpr std::uint64_t kMaxSplatVoxels = std::uint64_t(1) << 30;

// The coarsest resolution a splat takes: the lattice is anchored at the world origin, so a box that
// straddles one of its lines keeps two cells and a filter margin however wide the voxel, and below this
// the voxel cannot widen until the longest side holds `resolution` (1 or 2 gave voxels of 1e8 units).
inline constexpr int kMinSplatResolution = 8;

struct SplatOptions {
    // The voxel side in scene units; 0: the longest side of the spheres' bounding box / resolution.
    double voxel_size = 0.0;
    int resolution = 128;  // at least kMinSplatResolution
    double extinction_scale = 1.0;  // density = extinction / extinction_scale
    std::string grid_name = "density";
    // Also make "albedo": per voxel, the extinction-weighted mean of the spheres' grey albedo (mean of r,
    // g, b), 0 where the density is 0. Same lattice as the density grid.
    bool albedo_grid = false;
};

struct SplatGrids {
    DensityGrid density;
    DensityGrid albedo;  // empty (no values) unless options.albedo_grid
    double sphere_mass = 0.0;  // sum of extinction * 4/3 pi r^3; density.mass() * extinction_scale matches it
    std::size_t spheres = 0;   // spheres with mass (zero radius or extinction are skipped)
};

// Throws std::invalid_argument for a sphere with a non-finite centre, a radius, extinction or albedo that
// is negative or not finite (naming its index), options out of range, no sphere with mass, or a grid of
// more than kMaxSplatVoxels (naming the voxel count and the voxel size that would fit).
SplatGrids splat_spheres(const std::vector<Sphere>& spheres, const SplatOptions& options);

// splat_spheres' density grid alone (options.albedo_grid is ignored).
DensityGrid spheres_to_density_grid(const std::vector<Sphere>& spheres, const SplatOptions& options);

}  // namespace brume
