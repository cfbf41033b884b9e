// `brume vdb-info FILE.vdb` lists a file's grids; `brume vdb-import FILE.vdb -o SCENE.toml` writes a
// density grid as an ordinary scene of spheres (sim/vdb/vdb_import.h) and prints its measured error.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
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
    std::size_t max_spheres = 0;
    double extinction_scale = 1.0;
    std::vector<double> albedo{1.0, 1.0, 1.0};
};

void add_vdb_commands(CLI::App& app, VdbInfoArgs& info, VdbImportArgs& import);
int run_vdb_info(const VdbInfoArgs& args);
int run_vdb_import(const VdbImportArgs& args);

}  // namespace brume::app
