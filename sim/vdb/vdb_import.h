// A .vdb density grid as an ordinary scene: the sphere cloud, a camera framing it, default lighting, and
// the optical-depth error measured from that camera. What `brume vdb-import` writes.
#pragma once

#include "sim/scene.h"
#include "sim/density_grid.h"
#include "sim/vdb/optical_depth_error.h"
#include "sim/vdb/sphere_cloud.h"

#include <filesystem>
#include <string>

namespace brume {

struct VdbImport {
    Scene scene;
    double tolerance = 0.0;  // the one grid_to_spheres used
    std::uint64_t active_voxels = 0;
    double grid_mass = 0.0;    // integral of extinction over the grid
    double sphere_mass = 0.0;  // sum of extinction * volume over the spheres
    OpticalDepthError error;   // over the scene camera's pixel rays
};

// A camera outside the grid's bounding sphere, looking at its centre from the front (+z) and a little
// above, far enough that the whole cloud fits the default 40-degree view.
Camera frame_grid_camera(const DensityGrid& grid);

// Converts and measures an already read grid. Throws std::invalid_argument for bad options and
// std::runtime_error when the grid has no density at all (nothing to render).
VdbImport import_density_grid(const DensityGrid& grid, const SphereCloudOptions& options);

// read_density_grid (throws VdbError) then import_density_grid; scene.source is the file.
VdbImport import_vdb(const std::filesystem::path& path, const std::string& grid_name,
                     const SphereCloudOptions& options);

}  // namespace brume
