#include "sim/vdb/vdb_import.h"

#include "sim/vdb/vdb_file.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>

namespace brume {

Camera frame_grid_camera(const DensityGrid& grid) {
    Camera c;
    const glm::dvec3 lo = grid.world_min(), hi = grid.world_max();
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = 0.5 * glm::length(hi - lo);
    const double half_fov = c.fov_y_deg * 0.5 * 3.14159265358979323846 / 180.0;
    // The bounding sphere fills the vertical view with a 10% margin; the view is 4:3, wider than tall.
    c.position = centre + glm::normalize(glm::dvec3(0.0, 0.35, 1.0)) * (1.1 * radius / std::sin(half_fov));
    c.look_at = centre;
    c.up = {0.0, 1.0, 0.0};
    return c;
}

VdbImport import_density_grid(const DensityGrid& grid, const SphereCloudOptions& options) {
    SphereCloud cloud = grid_to_spheres(grid, options);
    if (cloud.spheres.empty())
        throw std::runtime_error("grid \"" + grid.name + "\" has no density (every active voxel is 0)");
    VdbImport out;
    out.tolerance = cloud.tolerance;
    out.active_voxels = grid.active_voxels;
    out.grid_mass = grid.mass() * options.extinction_scale;
    for (const Sphere& s : cloud.spheres)
        out.sphere_mass += s.extinction * 4.0 / 3.0 * 3.14159265358979323846 * s.radius * s.radius * s.radius;
    out.scene.camera = frame_grid_camera(grid);
    out.scene.spheres = std::move(cloud.spheres);
    out.error = measure_optical_depth_error(grid, options.extinction_scale, out.scene.spheres, out.scene.camera);
    return out;
}

VdbImport import_vdb(const std::filesystem::path& path, const std::string& grid_name,
                     const SphereCloudOptions& options) {
    const DensityGrid grid = read_density_grid(path, grid_name);
    VdbImport out;
    try {
        out = import_density_grid(grid, options);
    } catch (const std::invalid_argument&) {
        throw;
    } catch (const std::runtime_error& e) {
        throw VdbError(path.string() + ": " + e.what());
    }
    out.scene.source = path.string();
    return out;
}

}  // namespace brume
