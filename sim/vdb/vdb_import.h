// A .vdb density grid as an ordinary scene: the sphere cloud, a camera framing it, default lighting, and
// the optical-depth error measured from that camera. What `brume vdb-import` writes.
#pragma once

#include "sim/scene.h"
#include "sim/density_grid.h"
#include "sim/vdb/optical_depth_error.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/sphere_fit.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace brume {

struct VdbImport {
    std::string albedo_grid;  // the albedo grid used, or empty
    Scene scene;
    double split_threshold = 0.0;  // how grid_to_spheres made the cells (sim/vdb/sphere_cloud.h SphereCloud)
    int max_cell_voxels = 0;
    double lattice_spacing = 0.0;
    int clouds_tried = 0;
    bool fitted = false;        // options.fit: the spheres were fitted (sim/vdb/sphere_fit.h)
    int fit_rounds = 0;         // densification rounds of the fit
    bool met_tolerance = true;  // false only for a fit stopped by max_spheres first
    std::uint64_t active_voxels = 0;
    double grid_mass = 0.0;    // integral of extinction over the grid
    double sphere_mass = 0.0;  // sum of extinction * volume over the spheres
    OpticalDepthError error;   // over the conversion's views: the three axis views and the scene camera
    double seconds = 0.0;      // converting and measuring
};

// `camera` moved to look at the box's centre from the front (+z) and a little above, back far enough that
// the box's bounding sphere fills the narrower field of view with a 10% margin; up, field of view and
// size are kept.
Camera frame_box(Camera camera, const glm::dvec3& lo, const glm::dvec3& hi);

// The default camera framing the grid's voxels: what vdb-import writes.
Camera frame_grid_camera(const DensityGrid& grid);

// Converts and measures an already read grid. Throws std::invalid_argument for bad options and
// std::runtime_error when the grid has no density at all (nothing to render).
// With options.fit the spheres are fitted, `progress` called after every round.
VdbImport import_density_grid(const DensityGrid& grid, const SphereCloudOptions& options,
                              const std::function<void(const SphereFitProgress&)>& progress = {});

// Reads the grid from a file or a "builtin:NAME[:RES]" sample (sim/vdb/density_source.h), and an albedo
// grid as VdbVolume::albedo_grid says (unset: the file's "albedo" grid if any; "": none; a name: that
// grid), then import_density_grid; scene.source is the file. Throws VdbError naming the file for every
// problem with it.
VdbImport import_vdb(const std::filesystem::path& path, const std::string& grid_name, const SphereCloudOptions& options,
                     const std::optional<std::string>& albedo_grid = std::nullopt,
                     const std::function<void(const SphereFitProgress&)>& progress = {});

}  // namespace brume
