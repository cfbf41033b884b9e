#include "app/vdb_command.h"

#include "render/atomic_file.h"
#include "sim/scene_file.h"
#include "sim/vdb/vdb_file.h"
#include "sim/vdb/vdb_import.h"

#include <cstdio>

namespace brume::app {

void add_vdb_commands(CLI::App& app, VdbInfoArgs& info, VdbImportArgs& import) {
    CLI::App* list = app.add_subcommand("vdb-info", "List the grids of an OpenVDB file");
    list->add_option("file", info.file, "OpenVDB file (.vdb)")->required();

    CLI::App* cmd = app.add_subcommand("vdb-import", "Convert an OpenVDB density grid into a scene of spheres");
    cmd->add_option("file", import.file, "OpenVDB file (.vdb)")->required();
    cmd->add_option("-o,--output", import.output, "Scene file to write (TOML)")->required();
    cmd->add_option("--grid", import.grid, "Float grid to read")->capture_default_str();
    cmd->add_option("--tolerance", import.tolerance,
                    "A cell becomes one sphere when its densities spread by at most this fraction of its maximum")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--max-spheres", import.max_spheres,
                    "At most this many spheres: coarsens the tolerance by bisection until the count fits")
        ->check(CLI::Range(std::size_t(1), kMaxSpheres));
    cmd->add_option("--extinction-scale", import.extinction_scale, "Sphere extinction = density * this (per scene unit)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--albedo", import.albedo, "R,G,B single-scattering albedo, each in [0, 1]")
        ->delimiter(',')
        ->expected(3)
        ->check(CLI::Range(0.0, 1.0));
}

int run_vdb_info(const VdbInfoArgs& args) {
    const std::vector<VdbGridInfo> grids = list_vdb_grids(args.file);
    if (grids.empty()) std::printf("%s: no grids\n", args.file.c_str());
    for (const VdbGridInfo& g : grids) {
        std::printf("%-16s %-8s %-12s %10llu active voxels", g.name.c_str(), g.value_type.c_str(), g.grid_class.c_str(),
                    static_cast<unsigned long long>(g.active_voxels));
        if (g.active_voxels > 0)
            std::printf("  index [%d, %d, %d]..[%d, %d, %d]", g.bbox_min.x, g.bbox_min.y, g.bbox_min.z, g.bbox_max.x,
                        g.bbox_max.y, g.bbox_max.z);
        std::printf("  voxel %g x %g x %g\n", g.voxel_size.x, g.voxel_size.y, g.voxel_size.z);
    }
    return 0;
}

int run_vdb_import(const VdbImportArgs& args) {
    check_writable_path(args.output);  // refuse before the work, and write nothing on failure
    SphereCloudOptions options;
    options.tolerance = args.tolerance;
    options.max_spheres = args.max_spheres;
    options.extinction_scale = args.extinction_scale;
    options.albedo = {args.albedo[0], args.albedo[1], args.albedo[2]};
    const VdbImport im = import_vdb(args.file, args.grid, options);
    write_file_atomically(args.output, scene_to_toml(im.scene));
    const Camera& c = im.scene.camera;
    std::printf("%s: %zu spheres from %llu active voxels of grid \"%s\" (tolerance %g)\n", args.output.c_str(),
                im.scene.spheres.size(), static_cast<unsigned long long>(im.active_voxels), args.grid.c_str(),
                im.tolerance);
    std::printf("optical depth against the trilinear grid over the camera's %dx%d rays (%d meet the cloud): "
                "RMS %.2f%%, max %.2f%% (of the largest %.4g), bias %+.2f%%; extinction mass %.6g (grid %.6g)\n",
                c.width, c.height, im.error.rays, 100.0 * im.error.relative_rms, 100.0 * im.error.relative_max,
                im.error.max_grid_depth, 100.0 * im.error.bias, im.sphere_mass, im.grid_mass);
    return 0;
}

}  // namespace brume::app
