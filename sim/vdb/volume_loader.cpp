#include "sim/vdb/volume_loader.h"

#include "sim/camera_path.h"
#include "sim/scene_file.h"
#include "sim/vdb/conversion_cache.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/emitter_densities.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/sphere_fit.h"
#include "sim/vdb/vdb_file.h"
#include "sim/vdb/vdb_import.h"
#include "sim/volume_transform.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace brume {

namespace {

// The scene camera seen from the grid's side of the transform, at most 128 pixels across: the view the
// conversion must satisfy besides the axis views (a small image samples the same error statistics).
Camera camera_in_grid_space(const Camera& camera, const VolumeTransform& t) {
    Camera c = camera;
    c.position = world_to_volume(t, camera.position);
    c.look_at = world_to_volume(t, camera.look_at);
    c.up = glm::transpose(volume_rotation(t)) * camera.up;
    const int longest = std::max(camera.width, camera.height);
    if (longest > 128) {
        c.width = std::max(1, int(std::lround(camera.width * 128.0 / longest)));
        c.height = std::max(1, int(std::lround(camera.height * 128.0 / longest)));
    }
    return c;
}

}  // namespace

std::vector<VolumeReport> convert_scene_volumes(Scene& scene, const std::vector<Camera>& more_views) {
    struct Loaded {
        std::vector<DensityGrid> grids;  // density, then albedo when asked for
        std::chrono::steady_clock::time_point start;
    };
    // "FILE:LINE: vdb[i]", as the scene reader's own messages start.
    const auto table = [&](std::size_t i) {
        const std::string& at = scene.volumes[i].defined_at;
        return (at.empty() ? "" : at + ": ") + "vdb[" + std::to_string(i) + "]";
    };
    const auto where = [&](std::size_t i) {
        return table(i) + " (" + density_source_label(scene.volumes[i].source) + "): ";
    };
    // Read every grid first, so that a camera left to frame the volumes is placed before any conversion,
    // which measures its error from that camera.
    std::vector<Loaded> loaded;
    for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
        const VdbVolume& v = scene.volumes[i];
        Loaded l;
        l.start = std::chrono::steady_clock::now();
        std::vector<std::string> names{v.source.grid};
        if (v.albedo_grid && !v.albedo_grid->empty()) names.push_back(*v.albedo_grid);
        try {
            l.grids = read_density_source(v.source, names, v.albedo_grid ? "" : kDefaultAlbedoGrid);
        } catch (const VdbError& e) {
            throw VdbError(table(i) + ": " + e.what());
        }
        loaded.push_back(std::move(l));
    }
    if (scene.frame_volumes && !loaded.empty()) {
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        for (std::size_t i = 0; i < loaded.size(); ++i) {
            const DensityGrid& g = loaded[i].grids[0];
            const glm::dvec3 a = g.world_min(), b = g.world_max();
            for (int c = 0; c < 8; ++c) {
                const glm::dvec3 corner(c & 1 ? b.x : a.x, c & 2 ? b.y : a.y, c & 4 ? b.z : a.z);
                const glm::dvec3 w = volume_to_world(scene.volumes[i].transform, corner);
                lo = glm::min(lo, w);
                hi = glm::max(hi, w);
            }
        }
        scene.camera = frame_box(scene.camera, lo, hi);
    }
    std::vector<VolumeReport> reports;
    for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
        const VdbVolume& v = scene.volumes[i];
        const std::vector<DensityGrid>& grids = loaded[i].grids;
        VolumeReport report;
        report.source = density_source_label(v.source);
        try {
            SphereCloudOptions options;
            options.tolerance = v.tolerance;
            options.max_spheres = v.max_spheres;
            options.extinction_scale = v.extinction_scale;
            options.albedo = v.albedo;
            options.fit = v.fit;
            if (grids.size() > 1) options.albedo_grid = &grids[1];
            // A placement can shrink the voxels past what Brume reads in a file (sim/vdb/vdb_file.h):
            // scale 1e-200 put the conversion's views 1e200 grid units away, with no view direction left.
            const double placed_voxel = grids[0].voxel_size * v.transform.scale;
            if (!(placed_voxel >= kMinVoxelSize))
                throw std::runtime_error("scale " + toml_text::shortest(v.transform.scale) + " makes its voxels " +
                                         toml_text::shortest(placed_voxel) + " scene units, below the " +
                                         toml_text::shortest(kMinVoxelSize) + " Brume reads; raise the scale");
            options.views.push_back(camera_in_grid_space(scene.camera, v.transform));
            for (const Camera& c : more_views) options.views.push_back(camera_in_grid_space(c, v.transform));
            // Keyed on the grids and every option, views included (sim/vdb/conversion_cache.h): a farm's jobs
            // and a second render of the scene read the spheres instead of converting again.
            CacheOutcome cache = CacheOutcome::Off;
            const SphereCloud cloud =
                cached_conversion(grids[0], options, [&] { return convert_grid(grids[0], options); }, &cache);
            report.from_cache = cache == CacheOutcome::Hit;
            if (cloud.spheres.empty()) throw std::runtime_error("grid \"" + v.source.grid + "\" holds no density (every voxel is 0)");
            if (scene.spheres.size() + cloud.spheres.size() > kMaxSpheres)
                throw std::runtime_error(std::to_string(cloud.spheres.size()) + " spheres would take the scene past " +
                                         std::to_string(kMaxSpheres) + "; raise the tolerance or set max_spheres");
            // The grid was read within range (sim/vdb/vdb_file.h), but a transform can carry it past what a scene
            // file may hold, where the renderer's floats overflow (issue 14: NaN images with exit 0).
            for (const Sphere& s : cloud.spheres) {
                const Sphere w = volume_to_world(v.transform, s);
                const double reach = std::max({std::abs(w.center.x), std::abs(w.center.y), std::abs(w.center.z)}) + w.radius;
                if (!(reach <= kMaxCoordinate)) {
                    char text[200];
                    std::snprintf(text, sizeof text,
                                  "placed by its transform, the volume reaches %.4g scene units from the origin, past "
                                  "the %g a scene allows; lower its scale or translate",
                                  reach, kMaxCoordinate);
                    throw std::runtime_error(text);
                }
                scene.spheres.push_back(w);
            }
            report.spheres = cloud.spheres.size();
            report.active_voxels = grids[0].active_voxels;
            report.error = cloud.error;
        } catch (const std::exception& e) {  // bad options, an unreachable tolerance, no density
            throw VdbError(where(i) + e.what());
        }
        report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loaded[i].start).count();
        reports.push_back(report);
    }
    scene.volumes.clear();
    scene.frame_volumes = false;
    return reports;
}

std::vector<VolumeReport> prepare_preset(Preset& preset) {
    // A moving camera sees the cloud from wherever its path goes: four views spread over the timeline.
    std::vector<Camera> path_views;
    if (preset.camera_path.kind != CameraPath::Kind::Static && !preset.scene.volumes.empty()) {
        const double start = preset.timeline.preroll, length = preset.timeline.duration;
        for (int k = 0; k < 4; ++k) path_views.push_back(camera_at(preset, start + length * k / 3.0));
    }
    std::vector<VolumeReport> reports = convert_scene_volumes(preset.scene, path_views);
    load_emitter_densities(preset);
    return reports;
}

}  // namespace brume
