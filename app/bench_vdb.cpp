#include "app/bench_vdb.h"

#include "app/charts.h"
#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/output_paths.h"
#include "render/atomic_file.h"
#include "sim/usable_cpus.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/optical_depth_error.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/sphere_fit.h"
#include "sim/vdb/vdb_file.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <string>
#include <vector>

namespace brume::app {

namespace {

namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<double> parse_tolerances(const std::string& text) {
    std::vector<double> out;
    for (const std::string& item : split_commas(text)) {
        std::size_t used = 0;
        double t = 0.0;
        try {
            t = std::stod(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != item.size() || !(t > 0.0 && t <= 1.0))
            throw UsageError("--tolerances: '" + item + "' is not a tolerance in (0, 1]");
        out.push_back(t);
    }
    if (out.empty()) throw UsageError("--tolerances: none given");
    return out;
}

// The issue-13 ball: density 1 inside radius 1, voxels of 2 / n (0.04 at n = 50), centres symmetric about
// the origin. Not a built-in sample (those are made with OpenVDB's tools); one analytic sphere is its model.
DensityGrid uniform_ball(int n) {
    DensityGrid g;
    g.voxel_size = 2.0 / n;
    const int m = n + 4;  // a voxel of margin beyond the radius
    g.origin = glm::dvec3(-0.5 * (m - 1) * g.voxel_size);
    g.size = glm::ivec3(m);
    g.values.resize(std::size_t(m) * m * m);
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                const glm::dvec3 p = g.voxel_center(glm::dvec3(i, j, k));
                const float v = p.x * p.x + p.y * p.y + p.z * p.z < 1.0 ? 1.0f : 0.0f;
                g.values[g.offset(i, j, k)] = v;
                if (v != 0.0f) ++g.active_voxels;
            }
    return g;
}

}  // namespace

int run_bench_vdb(const BenchArgs& args) {
    const std::vector<int> sizes = parse_int_list(args.vdb_sizes);
    const std::vector<std::string> samples = split_commas(args.vdb_sample);
    if (samples.empty()) throw UsageError("--vdb-sample: none given");
    // Every name is checked before the output folder is made or any grid is read.
    for (const std::string& sample : samples)
        if (sample != "ball" && !is_sample_volume(sample))
            throw UsageError("--vdb-sample: no built-in volume '" + sample + "' (there are: ball, " +
                             sample_volume_names() + ")");
    const std::vector<double> tolerances = parse_tolerances(args.tolerances);
    for (const int n : sizes)
        if (n < kMinSampleResolution || n > kMaxSampleResolution)
            throw UsageError("--vdb-sizes: each resolution must be from " + std::to_string(kMinSampleResolution) + " to " +
                             std::to_string(kMaxSampleResolution) + " (got " + std::to_string(n) + ")");
    if (!args.output_dir.empty()) check_folder_can_be_made(args.output_dir);  // made when the figures are in
    std::printf("# brume bench vdb: built-in samples %s (builtin:NAME:N), spheres twice their cell's equal-volume radius;\n"
                "# error = RMS optical-depth error against the trilinear grid over three %dx%d axis views; 'voxels' is\n"
                "# one sphere per non-empty voxel; 'unseen' = the same error over three oblique 96x96 views neither\n"
                "# conversion measures (jittered rays); 'abs_err' = RMS difference / the largest grid depth; 'T_err' = mean |transmittance\n"
                "# difference| (the image error of an ambient-lit render); 'fit' rows are fitted (vdb-import --fit; 'tried' = rounds, '!' = the\n"
                "# default cap, %zu or one per 8 active voxels, stopped it above tolerance); sample 'ball' is a uniform ball of radius 1, 2/N voxels;\n"
                "# times on %u usable hardware threads\n",
                args.vdb_sample.c_str(), SphereCloudOptions{}.axis_view_resolution,
                SphereCloudOptions{}.axis_view_resolution, kDefaultFitSphereCap, usable_cpus());
    std::printf("# host: %s\n", host_cpu_description().c_str());
    std::printf("%-16s %9s %7s %9s %9s %8s %-15s %6s %8s %8s %8s %8s %8s %8s %8s\n", "grid", "voxels", "read_s",
                "tolerance", "spheres", "vox/sph", "cells", "tried", "conv_s", "rms_err", "max_err", "bias", "unseen",
                "abs_err", "T_err");
    std::ostringstream csv;
    csv << "grid,active_voxels,read_s,tolerance,spheres,cell_cap,threshold,lattice_spacing,clouds_tried,convert_s,rms_error,"
           "max_error,bias,unseen_rms_error,absolute_rms_error,transmittance_error\n";
    std::vector<VdbSeries> series;
    std::vector<std::pair<std::string, int>> grids;  // every sample at every size
    for (const std::string& sample : samples)
        for (const int n : sizes) grids.emplace_back(sample, n);
    for (const auto& [sample, n] : grids) {
        DensitySource source;
        source.file = "builtin:" + sample + ":" + std::to_string(n);
        const auto read_start = std::chrono::steady_clock::now();
        const DensityGrid grid = sample == "ball" ? uniform_ball(n) : read_density_source(source);
        const double read_s = seconds_since(read_start);
        const std::string label = sample + " " + std::to_string(n) + "^3";
        VdbSeries s{label, {}};
        const OpticalDepthViews unseen(grid, 1.0, grid_unseen_views(grid, 96), 0, PixelRays::Jittered);
        const auto row = [&](const std::string& tolerance, const std::vector<Sphere>& cloud, int cap, double threshold,
                             double spacing, int tried, double convert_s, const OpticalDepthError& e) {
            const std::size_t spheres = cloud.size();
            const OpticalDepthError u = unseen.measure(cloud);
            // How the cells were made: an octree (its size cap and spread threshold) or a resampled lattice.
            char cells[32];
            if (spacing < 0.0) std::snprintf(cells, sizeof cells, "fit");
            else if (cap < 0) std::snprintf(cells, sizeof cells, "one sphere");
            else if (spacing > 0.0) std::snprintf(cells, sizeof cells, "lattice %.2f", spacing);
            else if (cap == 1) std::snprintf(cells, sizeof cells, "voxels");
            else std::snprintf(cells, sizeof cells, "tree %d, %.3f", cap, threshold);
            std::printf("%-16s %9llu %7.2f %9s %9zu %8.1f %-15s %6d %8.2f %7.2f%% %7.1f%% %+7.2f%% %7.2f%% %7.2f%% %8.4f\n",
                        label.c_str(), static_cast<unsigned long long>(grid.active_voxels), read_s, tolerance.c_str(),
                        spheres, double(grid.active_voxels) / double(std::max<std::size_t>(spheres, 1)), cells, tried,
                        convert_s, 100.0 * e.relative_rms, 100.0 * e.relative_max, 100.0 * e.bias,
                        100.0 * u.relative_rms, 100.0 * e.absolute_rms, e.transmittance_mean);
            std::fflush(stdout);
            csv << json_string(label) << ',' << grid.active_voxels << ',' << read_s << ',' << tolerance << ',' << spheres
                << ',' << cap << ',' << threshold << ',' << spacing << ',' << tried << ',' << convert_s << ','
                << e.relative_rms << ',' << e.relative_max << ',' << e.bias << ',' << u.relative_rms << ',' << e.absolute_rms
                << ',' << e.transmittance_mean << '\n';
        };
        {  // The finest cloud: what every tolerance is measured against.
            const auto start = std::chrono::steady_clock::now();
            SphereCloudOptions o;
            o.max_cell_voxels = 1;
            const std::vector<Sphere> spheres = grid_to_spheres_at(grid, o, 0.0);
            const OpticalDepthError e = OpticalDepthViews(grid, 1.0, grid_axis_views(grid, o.axis_view_resolution)).measure(spheres);
            row("voxels", spheres, 1, 0.0, 0.0, 1, seconds_since(start), e);
            s.points.emplace_back(double(spheres.size()), e.relative_rms);
        }
        if (sample == "ball") {  // its model: one sphere of radius 1, the grid's density
            Sphere analytic;
            analytic.radius = 1.0;
            analytic.extinction = 1.0;
            const OpticalDepthError e = OpticalDepthViews(grid, 1.0, grid_axis_views(grid, SphereCloudOptions{}.axis_view_resolution)).measure({analytic});
            row("analytic", {analytic}, -1, 0.0, 0.0, 0, 0.0, e);
        }
        for (const double tolerance : tolerances) {
            SphereCloudOptions o;
            o.tolerance = tolerance;
            const auto start = std::chrono::steady_clock::now();
            char text[32];
            std::snprintf(text, sizeof text, "%g", tolerance);
            try {
                const SphereCloud cloud = grid_to_spheres(grid, o);
                row(text, cloud.spheres, cloud.max_cell_voxels, cloud.split_threshold, cloud.lattice_spacing,
                    cloud.clouds_tried, seconds_since(start), cloud.error);
                s.points.emplace_back(double(cloud.spheres.size()), cloud.error.relative_rms);
            } catch (const ToleranceUnreachable& e) {
                std::printf("%-16s %9llu %7.2f %9s  unreachable: the finest cloud measures %.2f%%\n", label.c_str(),
                            static_cast<unsigned long long>(grid.active_voxels), read_s, text, 100.0 * e.finest_error());
            }
        }
        // Fitting (sim/vdb/sphere_fit.h) at the same tolerances, measured over the same axis views as the
        // tiling rows (the fit measures itself over its 25 fitting views and stops on 8 held-out ones; its
        // own figures are in the progress).
        VdbSeries fitted{label + " fit", {}};
        const OpticalDepthViews axis_views(grid, 1.0, grid_axis_views(grid, SphereCloudOptions{}.axis_view_resolution));
        for (const double tolerance : tolerances) {
            SphereCloudOptions o;
            o.tolerance = tolerance;
            // No max_spheres: vdb-import --fit's default cap, which also bounds the time a tolerance the grid
            // cannot reach (the sheet's voxel-level floor) costs.
            char text[32];
            std::snprintf(text, sizeof text, "%g", tolerance);
            const auto start = std::chrono::steady_clock::now();
            const SphereFit fit = fit_spheres(grid, o);
            const double convert_s = seconds_since(start);
            const OpticalDepthError e = axis_views.measure(fit.spheres);
            row(std::string(text) + (fit.met_tolerance ? "" : "!"), fit.spheres, 0, 0.0, -1.0, fit.rounds, convert_s, e);
            fitted.points.emplace_back(double(fit.spheres.size()), e.relative_rms);
        }
        std::sort(s.points.begin(), s.points.end());
        series.push_back(std::move(s));
        std::sort(fitted.points.begin(), fitted.points.end());
        series.push_back(std::move(fitted));
    }
    if (!args.output_dir.empty()) {
        const fs::path dir(args.output_dir);
        make_folder(dir);
        write_file_atomically(dir / "results_vdb.csv", csv.str());
        std::printf("wrote %s\n", (dir / "results_vdb.csv").c_str());
        for (const std::string& f : write_vdb_chart(dir, series)) std::printf("wrote %s\n", f.c_str());
    }
    return 0;
}

}  // namespace brume::app
