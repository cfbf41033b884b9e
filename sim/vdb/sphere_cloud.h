// A density grid as a cloud of spheres (docs/vdb.md), the fewest that meet a stated error.
//
// Cells. An adaptive octree over the grid's voxels: a cell whose densities spread (max - min) by at most a
// threshold becomes one sphere, so uniform regions cost one sphere, not one per voxel. A sphere keeps its
// cell's mass (sum of extinction * volume), so the cloud's total extinction mass equals the grid's exactly.
//
// Shape. Spheres cannot tile space, so a lattice of them has optical depth that ripples at the lattice's
// frequency. Spheres of their cell's volume (radius r_v) ripple by about 10% RMS whatever the cells, a floor
// no threshold can lower. The ripple's amplitude is the sphere's Fourier transform at the lattice frequency,
// 3 (sin x - x cos x) / x^3 with x = 2 pi r / cell side: 0.11 at r = r_v, 0.004 at r = 2 r_v. So each sphere
// is `sphere_scale` times r_v in radius with 1 / sphere_scale^3 of the extinction (mass unchanged): the
// spheres overlap their neighbours, which exact overlap integration (ppll) renders without artefacts, at
// about sphere_scale^2 more fragments per pixel (docs/vdb.md has the measurements).
//
// Tolerance. The error that counts is optical depth along rays, so that is what `tolerance` bounds: the
// relative RMS difference between the spheres' optical depth and the trilinear grid's, measured exactly
// (sim/vdb/optical_depth_error.h) over the pixel rays of the three axis views and any views given (a
// scene's camera). The octree's two knobs, the spread threshold and a cap on cell size, and the spacing of
// a resampled lattice (sim/vdb/sphere_lattice.h) are searched for the fewest spheres that measure within
// tolerance.
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"
#include "sim/vdb/optical_depth_error.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace brume {

inline constexpr double kDefaultSphereScale = 2.0;
inline constexpr double kMinSphereScale = 1.0;
inline constexpr double kMaxSphereScale = 4.0;

struct SphereCloudOptions {
    // The relative RMS optical-depth error the cloud must meet, in (0, 1].
    double tolerance = 0.05;
    // When > 0, instead of tolerance: the most accurate cloud (the finest octree) of at most this many spheres.
    std::size_t max_spheres = 0;
    double extinction_scale = 1.0;  // extinction = density * extinction_scale, per grid unit
    glm::dvec3 albedo{1.0};
    // Optional, in the grid's space: each sphere's albedo is `albedo` times this grid's value, clamped to
    // [0, 1]: its density-weighted mean over an octree cell's voxels, its value at a lattice cell's centre.
    const DensityGrid* albedo_grid = nullptr;
    double sphere_scale = kDefaultSphereScale;  // sphere radius / the radius of its cell's volume
    // For grid_to_spheres_at: cells at most this many voxels on a side; 0: no limit. grid_to_spheres
    // searches it.
    int max_cell_voxels = 0;
    // Views, in the grid's space, that the error is measured over besides the three axis views.
    std::vector<Camera> views;
    int axis_view_resolution = 96;  // pixels across each axis view
    int threads = 0;                // for measuring; 0: every usable CPU
    // import_density_grid (sim/vdb/vdb_import.h): fit the spheres (sim/vdb/sphere_fit.h) instead of tiling;
    // then max_spheres caps the fit rather than replacing the tolerance.
    bool fit = false;
};

struct SphereCloud {
    std::vector<Sphere> spheres;
    OpticalDepthError error;      // measured over every view
    double split_threshold = 0.0;  // the octree's density spread, as a fraction of the grid's largest density
    int max_cell_voxels = 0;       // and its cell-size cap (0: none)
    double lattice_spacing = 0.0;  // > 0: the spheres are a resampled lattice of this spacing, in voxels
                                   // (sim/vdb/sphere_lattice.h), not octree cells
    int clouds_tried = 0;          // conversions measured on the way
    // Set by fit_sphere_cloud (sim/vdb/sphere_fit.h): the spheres were fitted, in this many rounds, and met
    // the tolerance (false only where an explicit max_spheres stopped the fit first).
    bool fitted = false;
    int fit_rounds = 0;
    bool met_tolerance = true;
};

// What a cloud of one sphere per non-empty voxel measures when that is still above tolerance.
class ToleranceUnreachable : public std::runtime_error {
public:
    ToleranceUnreachable(double tolerance, std::size_t finest_spheres, double finest_error);
    double finest_error() const { return finest_error_; }

private:
    double finest_error_;
};

// Throws std::invalid_argument for options out of range, ToleranceUnreachable as above. An all-zero
// grid gives no spheres.
SphereCloud grid_to_spheres(const DensityGrid& grid, const SphereCloudOptions& options);

// Sum of extinction * 4/3 pi r^3: the integral of extinction over the spheres (overlaps add). Every
// conversion keeps it equal to the grid's mass times the extinction scale.
double spheres_extinction_mass(const std::vector<Sphere>& spheres);

// The cloud at a given octree threshold, unmeasured (benchmarks chart count against threshold).
std::vector<Sphere> grid_to_spheres_at(const DensityGrid& grid, const SphereCloudOptions& options, double split_threshold);

}  // namespace brume
