// Reading a DensitySource (sim/scene.h): a .vdb file, its relative path taken against the directory of the
// scene or preset that names it, or "builtin:NAME[:RESOLUTION]", a sample volume made in memory
// (sim/vdb/vdb_file.h sample_volumes, RESOLUTION 64 when left out) and decoded by the same reader, so a
// built-in preset exercises exactly the path a user's file takes.
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace brume {

inline constexpr int kDefaultSampleResolution = 64;
// The albedo grid a volume uses when it names none and the file has one: what vdb-export writes.
inline constexpr const char* kDefaultAlbedoGrid = "albedo";

// How messages name the source: the resolved path, or the "builtin:..." text as written.
std::string density_source_label(const DensitySource& source);

// The file a non-built-in source reads: base_dir / file for a relative file.
std::filesystem::path density_source_path(const DensitySource& source);

// The grids of one source, in the order of grid_names, the file parsed once. Throws VdbError naming the
// source for every problem read_density_grid reports, an unknown built-in or a malformed resolution.
// `if_present`: as decode_density_grids (sim/vdb/vdb_file.h), a float grid appended when the file has it.
std::vector<DensityGrid> read_density_source(const DensitySource& source, const std::vector<std::string>& grid_names,
                                             const std::string& if_present = "");

// The grid source.grid.
DensityGrid read_density_source(const DensitySource& source);

}  // namespace brume
