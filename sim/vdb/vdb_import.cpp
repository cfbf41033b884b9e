#include "sim/vdb/vdb_import.h"

#include "sim/scene_file.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/vdb_file.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace brume {
namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

Camera frame_box(Camera camera, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-9);
    const double tan_half_y = std::tan(camera.fov_y_deg * 0.5 * 3.14159265358979323846 / 180.0);
    const double half_angle = std::atan(tan_half_y * std::min(1.0, double(camera.width) / double(camera.height)));
    glm::dvec3 back = glm::normalize(glm::dvec3(0.0, 0.35, 1.0));
    if (glm::length(glm::cross(back, camera.up)) < 1e-6 * glm::length(camera.up)) back = glm::dvec3(1.0, 0.0, 0.0);
    camera.position = centre + back * (1.1 * radius / std::sin(half_angle));
    camera.look_at = centre;
    return camera;
}

Camera frame_grid_camera(const DensityGrid& grid) { return frame_box(Camera{}, grid.world_min(), grid.world_max()); }

VdbImport import_density_grid(const DensityGrid& grid, const SphereCloudOptions& options,
                              const std::function<void(const SphereFitProgress&)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    SphereCloudOptions with_camera = options;
    const Camera camera = frame_grid_camera(grid);
    with_camera.views.push_back(camera);
    VdbImport out;
    SphereCloud cloud = convert_grid(grid, with_camera, progress);
    out.fitted = cloud.fitted;
    out.fit_rounds = cloud.fit_rounds;
    out.met_tolerance = cloud.met_tolerance;
    if (cloud.spheres.empty())
        throw std::runtime_error("grid \"" + grid.name + "\" has no density (every active voxel is 0)");
    // The scene the spheres go into must read back: its extinction is bounded (sim/scene_file.h). An
    // extinction scale of 1e300 made infinite spheres and a NaN error report, with exit 0.
    double densest = 0.0;
    for (const Sphere& s : cloud.spheres) densest = std::max(densest, std::isfinite(s.extinction) ? s.extinction : kInfinity);
    if (densest > kMaxExtinction)
        throw std::invalid_argument("extinction scale " + toml_text::shortest(options.extinction_scale) + " makes grid \"" +
                                    grid.name + "\"'s spheres " + toml_text::shortest(densest) +
                                    " per unit, above a scene's limit of " + toml_text::shortest(kMaxExtinction) +
                                    ": lower the extinction scale");
    out.split_threshold = cloud.split_threshold;
    out.max_cell_voxels = cloud.max_cell_voxels;
    out.lattice_spacing = cloud.lattice_spacing;
    out.clouds_tried = cloud.clouds_tried;
    out.error = cloud.error;
    out.active_voxels = grid.active_voxels;
    out.grid_mass = grid.mass() * options.extinction_scale;
    out.sphere_mass = spheres_extinction_mass(cloud.spheres);
    out.scene.camera = camera;
    out.scene.spheres = std::move(cloud.spheres);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

VdbImport import_vdb(const std::filesystem::path& path, const std::string& grid_name, const SphereCloudOptions& options,
                     const std::optional<std::string>& albedo_grid,
                     const std::function<void(const SphereFitProgress&)>& progress) {
    DensitySource source;
    source.file = path.string();
    source.grid = grid_name;
    std::vector<std::string> names{grid_name};
    if (albedo_grid && !albedo_grid->empty()) names.push_back(*albedo_grid);
    const std::vector<DensityGrid> grids = read_density_source(source, names, albedo_grid ? "" : kDefaultAlbedoGrid);
    SphereCloudOptions with_albedo = options;
    if (grids.size() > 1) with_albedo.albedo_grid = &grids[1];
    VdbImport out;
    try {
        out = import_density_grid(grids[0], with_albedo, progress);
    } catch (const std::invalid_argument&) {
        throw;
    } catch (const std::runtime_error& e) {  // no density, an unreachable tolerance
        throw VdbError(path.string() + ": " + e.what());
    }
    out.scene.source = path.string();
    if (grids.size() > 1) out.albedo_grid = grids[1].name;
    return out;
}

}  // namespace brume
