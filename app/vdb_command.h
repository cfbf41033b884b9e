// `brume vdb-info FILE.vdb` lists a file's grids; `brume vdb-import FILE.vdb -o SCENE.toml` writes a
// density grid as an ordinary scene of spheres (sim/vdb/vdb_import.h) and prints its measured error;
// `brume vdb-export PRESET -o OUT.vdb` writes a simulated frame's spheres as a density grid
// (sim/vdb/particle_splat.h) for other VFX tools; `brume vdb-sample NAME -o OUT.vdb` writes a built-in
// sample volume, so there are real files to try vdb-import on.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace brume::app {

struct VdbInfoArgs {
    std::string file;
};

struct VdbImportArgs {
    std::string file;
    std::string grid = "density";
    std::string output;
    double tolerance = 0.05;
    bool tolerance_set = false;  // given on the command line (its default is not a request)
    std::size_t max_spheres = 0;
    double extinction_scale = 1.0;
    std::vector<double> albedo{1.0, 1.0, 1.0};
    std::optional<std::string> albedo_grid;  // unset: the file's "albedo" grid if any; "": none
    double sphere_scale = 2.0;
    bool fit = false;  // fit the spheres (sim/vdb/sphere_fit.h) instead of tiling
};

struct VdbExportArgs {
    std::string input;  // preset name or file, or scene file
    int frame = -1;     // -1: the last
    bool frame_set = false;
    double voxel_size = 0.0;  // 0: from resolution
    int resolution = 128;
    double extinction_scale = 1.0;
    bool albedo_grid = false;
    std::string output;
};

struct VdbSampleArgs {
    std::string name;
    int resolution = 0;  // set to the sample default when the command is added
    std::string output;
    bool list = false;
};

void add_vdb_commands(CLI::App& app, VdbInfoArgs& info, VdbImportArgs& import);
void add_vdb_export_commands(CLI::App& app, VdbExportArgs& export_args, VdbSampleArgs& sample);
int run_vdb_info(const VdbInfoArgs& args);
int run_vdb_import(const VdbImportArgs& args);
int run_vdb_export(const VdbExportArgs& args);
int run_vdb_sample(const VdbSampleArgs& args);

}  // namespace brume::app
