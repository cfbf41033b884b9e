#include "app/vdb_command.h"

#include "app/cli_util.h"
#include "app/output_paths.h"
#include "app/standard_streams.h"

#include "render/atomic_file.h"
#include "sim/builtin_presets.h"
#include "sim/scene_file.h"
#include "sim/simulator.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/particle_splat.h"
#include "sim/vdb/sphere_fit.h"
#include "sim/vdb/vdb_file.h"
#include "sim/vdb/vdb_import.h"
#include "sim/vdb/volume_loader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace brume::app {

void add_vdb_commands(CLI::App& app, VdbInfoArgs& info, VdbImportArgs& import) {
    CLI::App* list = app.add_subcommand("vdb-info", "List the grids of an OpenVDB file");
    list->add_option("file", info.file, "OpenVDB file (.vdb)")->required();

    CLI::App* cmd = app.add_subcommand("vdb-import", "Convert an OpenVDB density grid into a scene of spheres");
    cmd->add_option("file", import.file, "OpenVDB file (.vdb), or builtin:NAME[:RES] (brume vdb-sample --list)")->required();
    cmd->add_option("-o,--output", import.output, "Scene file to write (TOML; - for standard output)")->required();
    cmd->add_option("--grid", import.grid, "Float grid to read")->capture_default_str();
    cmd->add_option("--tolerance", import.tolerance,
                    "Relative RMS optical-depth error the spheres must meet against the grid, in (0, 1]")
        ->check(refuse_outside_half_open_unit)
        ->each([&import](const std::string&) { import.tolerance_set = true; })
        ->capture_default_str();
    cmd->add_option("--max-spheres", import.max_spheres,
                    "Instead of --tolerance (with --fit, beside it): the most accurate cloud of at most this many spheres")
        ->check(CLI::Range(std::size_t(1), kMaxSpheres));
    cmd->add_option("--extinction-scale", import.extinction_scale, "Sphere extinction = density * this (per scene unit)")
        ->check(refuse_non_positive)
        ->capture_default_str();
    cmd->add_option("--albedo", import.albedo, "R,G,B single-scattering albedo, each in [0, 1]")
        ->delimiter(',')
        ->expected(3)
        ->check(refuse_outside_unit_interval);
    cmd->add_option("--albedo-grid", import.albedo_grid,
                    "Float grid of the same file multiplying the albedo per sphere (default: \"albedo\" if the "
                    "file has one; \"\" for none)");
    cmd->add_option("--sphere-scale", import.sphere_scale,
                    "Sphere radius / its cell's equal-volume radius: 1 leaves ~10% lattice ripple, 2 (default) ~0.4%")
        ->check(CLI::Range(kMinSphereScale, kMaxSphereScale))
        ->capture_default_str();
    cmd->add_flag("--fit", import.fit,
                  "Fit sphere centres, radii and extinctions to the grid's optical depth (far fewer spheres than "
                  "tiling); stops at --tolerance, or at --max-spheres if that comes first");
}

void add_vdb_export_commands(CLI::App& app, VdbExportArgs& export_args, VdbSampleArgs& sample) {
    CLI::App* cmd = app.add_subcommand("vdb-export", "Write a simulated frame's spheres as an OpenVDB density grid");
    cmd->add_option("input", export_args.input, "Preset file or built-in name (see brume play --list), or a scene file; - reads it from standard input")
        ->required();
    cmd->add_option("-o,--output", export_args.output, "OpenVDB file to write (.vdb; - for standard output)")->required();
    cmd->add_option("--frame", export_args.frame, "Frame to export, 0-based (default: the last)")
        ->each([&export_args](const std::string&) { export_args.frame_set = true; });
    CLI::Option* voxel = cmd->add_option("--voxel-size", export_args.voxel_size, "Voxel side in scene units")
                             ->check(refuse_non_positive);
    CLI::Option* resolution =
        cmd->add_option("--resolution", export_args.resolution,
                        "Voxels across the longest side of the spheres' bounding box (when no --voxel-size; at least " +
                            std::to_string(kMinSplatResolution) + ")")
            ->check([](const std::string& text) {
                const std::optional<long long> v = parse_whole_number(text);
                return v && *v >= kMinSplatResolution && *v <= std::numeric_limits<int>::max()
                           ? std::string()
                           : "not a whole number of voxels from " + std::to_string(kMinSplatResolution) + " up (got \"" +
                                 text.substr(0, 40) + "\")";
            })
            ->capture_default_str();
    voxel->excludes(resolution);
    cmd->add_option("--extinction-scale", export_args.extinction_scale,
                    "Grid density = sphere extinction / this (vdb-import's --extinction-scale reverses it)")
        ->check(refuse_non_positive)
        ->capture_default_str();
    cmd->add_flag("--albedo-grid", export_args.albedo_grid,
                  "Also write a grid \"albedo\": the extinction-weighted mean grey albedo per voxel");

    sample.resolution = kDefaultSampleResolution;
    CLI::App* s = app.add_subcommand("vdb-sample", "Write a built-in sample volume as an OpenVDB file");
    s->add_option("name", sample.name, "Sample volume (see --list)");
    s->add_option("-o,--output", sample.output, "OpenVDB file to write (.vdb; - for standard output)");
    s->add_option("--resolution", sample.resolution, "Voxels across the volume's [-1, 1] box")
        ->check(CLI::Range(kMinSampleResolution, kMaxSampleResolution))
        ->capture_default_str();
    s->add_flag("--list", sample.list, "List the sample volumes and exit");
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
    // As a [[vdb]] table: a tiling meets a tolerance or spends a number of spheres, not both; a fit stops
    // at whichever comes first. Given both, --max-spheres used to win silently over the tolerance asked.
    if (args.tolerance_set && args.max_spheres > 0 && !args.fit)
        throw UsageError("give --tolerance or --max-spheres, not both (--tolerance: the accuracy to meet; --max-spheres: "
                         "the most spheres to spend; with --fit, both: the fit stops at whichever comes first)");
    check_output_format("-o", args.output, ".toml");
    check_writable_path(args.output);  // refuse before the work, and write nothing on failure
    check_outputs_distinct({{"-o", args.output}}, {{"the VDB file", args.file}});
    if (names_standard_output(args.output)) claim_standard_output("-o", false);
    SphereCloudOptions options;
    options.tolerance = args.tolerance;
    options.max_spheres = args.max_spheres;
    options.extinction_scale = args.extinction_scale;
    options.albedo = {args.albedo[0], args.albedo[1], args.albedo[2]};
    options.sphere_scale = args.sphere_scale;
    options.fit = args.fit;
    // The fit reports each round on stderr (stdout keeps the summary): one line per round, so the falling
    // error reads the same on a terminal and in a log. The bar is the way from the first round's error to
    // the goal, on a log scale (the error falls about as a power of the count, docs/vdb.md): the fit is done
    // when both errors are there, the fitting views' at the tolerance and the held-out views' within
    // kValidationMargin of it, so the bar follows whichever is further.
    double first_behind = 0.0;
    const auto progress = [&first_behind, tolerance = args.tolerance](const SphereFitProgress& p) {
        const double behind = std::max(p.error, p.validation / kValidationMargin);
        if (p.round == 1) first_behind = behind;
        double done = behind <= tolerance ? 1.0 : 0.0;
        if (behind > tolerance && first_behind > tolerance)
            done = std::clamp(std::log(first_behind / behind) / std::log(first_behind / tolerance), 0.0, 1.0);
        constexpr int kWidth = 20;
        char bar[kWidth + 1];
        const int filled = int(std::floor(done * kWidth + 1e-9));
        for (int k = 0; k < kWidth; ++k) bar[k] = k < filled ? '#' : '-';
        bar[kWidth] = '\0';
        std::fprintf(stderr,
                     "fit round %2d [%s] %3.0f%%: %7zu spheres, RMS optical-depth error %6.2f%% (held-out views %6.2f%%) (%.1f s)\n",
                     p.round, bar, 100.0 * done, p.spheres, 100.0 * p.error, 100.0 * p.validation, p.seconds);
    };
    const VdbImport im = import_vdb(args.file, args.grid, options, args.albedo_grid, progress);
    write_file_atomically(args.output, scene_to_toml(im.scene));
    const Camera& c = im.scene.camera;
    char cells[96];
    if (im.fitted)
        std::snprintf(cells, sizeof cells, "fitted in %d rounds%s", im.fit_rounds,
                      im.met_tolerance ? "" : ", stopped by --max-spheres above the tolerance");
    else if (im.lattice_spacing > 0.0) std::snprintf(cells, sizeof cells, "a lattice of %.3g-voxel cells", im.lattice_spacing);
    else if (im.max_cell_voxels == 1) std::snprintf(cells, sizeof cells, "one sphere per voxel");
    else std::snprintf(cells, sizeof cells, "octree cells of at most %d voxels, spread %.3g", im.max_cell_voxels, im.split_threshold);
    char goal[64];
    if (args.fit && args.max_spheres > 0)
        std::snprintf(goal, sizeof goal, "tolerance %g, at most %zu spheres", args.tolerance, args.max_spheres);
    else if (args.max_spheres > 0) std::snprintf(goal, sizeof goal, "at most %zu spheres", args.max_spheres);
    else std::snprintf(goal, sizeof goal, "tolerance %g", args.tolerance);
    const std::string tint = im.albedo_grid.empty() ? "" : ", albedo from grid \"" + im.albedo_grid + "\"";
    std::printf("%s: %zu spheres from %llu active voxels of grid \"%s\"%s (%s: %s; %d clouds measured, %.2f s)\n",
                shown_output_name(args.output).c_str(), im.scene.spheres.size(), static_cast<unsigned long long>(im.active_voxels),
                args.grid.c_str(), tint.c_str(), goal, cells, im.clouds_tried, im.seconds);
    std::printf("optical depth against the trilinear grid over the %s and the %dx%d camera (%lld rays meet "
                "the cloud): RMS %.2f%%, max %.2f%% (of the largest %.4g), bias %+.2f%%; extinction mass %.6g (grid "
                "%.6g)\n"
                "absolute RMS %.3f%% of the largest optical depth; mean transmittance difference %.4f (the image error "
                "of an ambient-lit render)\n",
                im.fitted ? "25 fitting views" : "axis views", c.width, c.height, static_cast<long long>(im.error.rays), 100.0 * im.error.relative_rms,
                100.0 * im.error.relative_max, im.error.max_grid_depth, 100.0 * im.error.bias, im.sphere_mass,
                im.grid_mass, 100.0 * im.error.absolute_rms, im.error.transmittance_mean);
    return 0;
}

int run_vdb_export(const VdbExportArgs& args) {
    check_output_format("-o", args.output, ".vdb");
    check_writable_path(args.output);  // refuse before the work, and write nothing on failure
    check_outputs_distinct({{"-o", args.output}}, {{"the preset", args.input}});  // a built-in name is no file
    if (names_standard_output(args.output)) claim_standard_output("-o", true);
    Preset preset = resolve_preset(input_path(args.input));  // "-": standard input
    // A document without emitters (a scene file, a static preset) is the same at every frame: its spheres.
    const bool animated = !preset.emitters.empty();
    const int frames = preset.timeline.frame_count();
    const int frame = args.frame_set ? args.frame : frames - 1;
    if (args.frame_set && !animated)
        throw UsageError("--frame picks a frame of a preset with emitters; " + preset.scene.source +
                         " has none, so its spheres are the same at every frame: leave --frame out");
    if (animated && (frame < 0 || frame >= frames))
        throw UsageError("--frame " + std::to_string(frame) + " is outside " + preset.name + "'s frames 0-" +
                         std::to_string(frames - 1));
    prepare_preset(preset);  // [[vdb]] volumes become spheres, density emitters get their grids

    // The spheres a renderer gets for this frame, in its order: the scene's own, then the particles
    // (as `brume play` builds each frame).
    std::vector<Sphere> spheres = preset.scene.spheres;
    if (animated) {
        Simulator sim(preset);
        sim.advance_to_frame(frame);
        sim.append_spheres(spheres);
        if (sim.skipped() > 0)  // a silent cap looks like a weak emitter, as render and play say
            std::printf("note: the particle budget max_particles = %u skipped %llu births up to frame %d\n",
                        preset.timeline.max_particles, static_cast<unsigned long long>(sim.skipped()), frame);
    }
    const std::string what = animated ? "frame " + std::to_string(frame) + " of " + preset.name : preset.scene.source;
    if (spheres.empty()) throw std::runtime_error(what + " has no spheres: nothing to export");

    SplatOptions options;
    options.voxel_size = args.voxel_size;
    options.resolution = args.resolution;
    options.extinction_scale = args.extinction_scale;
    options.albedo_grid = args.albedo_grid;
    const SplatGrids grids = splat_spheres(spheres, options);
    std::vector<DensityGrid> out{grids.density};
    if (args.albedo_grid) out.push_back(grids.albedo);
    write_file_atomically(args.output, encode_vdb(out));

    const DensityGrid& g = grids.density;
    const double grid_mass = g.mass() * args.extinction_scale;
    std::printf("%s: %s, %zu spheres -> grid \"%s\"%s of %d x %d x %d = %zu voxels of %.6g (%llu active)\n",
                shown_output_name(args.output).c_str(), what.c_str(), grids.spheres, g.name.c_str(), args.albedo_grid ? " and \"albedo\"" : "",
                g.size.x, g.size.y, g.size.z, g.voxel_count(), g.voxel_size,
                static_cast<unsigned long long>(g.active_voxels));
    std::printf("extinction mass: grid %.9g (density x %g), spheres %.9g, relative difference %.2g\n", grid_mass,
                args.extinction_scale, grids.sphere_mass, std::abs(grid_mass - grids.sphere_mass) / grids.sphere_mass);
    return 0;
}

int run_vdb_sample(const VdbSampleArgs& args) {
    if (args.list) {
        for (const SampleVolumeInfo& s : sample_volumes()) std::printf("%-12s %s\n", s.name, s.description);
        return 0;
    }
    const std::string names = sample_volume_names();
    if (args.name.empty()) throw UsageError("vdb-sample needs a NAME: one of " + names + " (or --list)");
    if (!is_sample_volume(args.name))
        throw UsageError("no sample volume named \"" + args.name + "\" (there are: " + names + ")");
    if (args.output.empty()) throw UsageError("vdb-sample needs -o OUT.vdb");
    check_output_format("-o", args.output, ".vdb");
    check_writable_path(args.output);
    if (names_standard_output(args.output)) claim_standard_output("-o", true);
    const std::string bytes = encode_sample_volume_vdb(args.name, args.resolution);
    write_file_atomically(args.output, bytes);
    const double voxel = 2.0 / args.resolution;
    std::printf("%s: sample volume %s, grid \"density\" at %d voxels across [-1, 1]^3 (voxel %g), %zu bytes\n",
                shown_output_name(args.output).c_str(), args.name.c_str(), args.resolution, voxel, bytes.size());
    return 0;
}

}  // namespace brume::app
