// OpenVDB files: the one place Brume includes OpenVDB (vdb_file.cpp). Reading lists grids and copies a
// float grid into a DensityGrid; writing encodes DensityGrids (vdb-export, test data) and makes sample
// files with OpenVDB's own tools, since the project has no internet to fetch real ones from.
#pragma once

#include "sim/density_grid.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {

// what() names the file and the problem: "cloud.vdb: no grid named \"density\" (grids: \"smoke\")".
class VdbError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct VdbGridInfo {
    std::string name;
    std::string value_type;  // OpenVDB's name: "float", "vec3s", "int32", ...
    std::string grid_class;  // "fog volume", "level set", "staggered", "unknown"
    std::uint64_t active_voxels = 0;
    glm::ivec3 bbox_min{0};  // active voxel bounding box, inclusive; meaningless when active_voxels is 0
    glm::ivec3 bbox_max{0};
    glm::dvec3 voxel_size{0.0};
};

// Every grid in the file, in file order. Throws VdbError for a missing, unreadable, truncated or
// corrupted file.
std::vector<VdbGridInfo> list_vdb_grids(const std::filesystem::path& path);

// Copies the float grid `grid_name` with its transform. Throws VdbError when the file is missing,
// unreadable, truncated or corrupted, has no such grid (the message lists the names it has), the grid
// holds another value type, has no active voxels, a non-zero background, a negative or non-finite value,
// or a transform other than a uniform scale and a translation.
DensityGrid read_density_grid(const std::filesystem::path& path, const std::string& grid_name = "density");

// The whole file, for decode_density_grids; VdbError when it is missing, a directory or unreadable.
std::string read_vdb_bytes(const std::filesystem::path& path);

// As read_density_grid, for several grids of one file's bytes parsed once; `source` names the bytes in
// messages (a path, or "builtin:cloud"). The result is in the order of grid_names, followed by the float
// grid `if_present` when the file holds one of that name (checked like the others once it is there).
std::vector<DensityGrid> decode_density_grids(const std::string& bytes, const std::string& source,
                                              const std::vector<std::string>& grid_names,
                                              const std::string& if_present = "");

// The bytes of a .vdb file holding `grid` as a float fog volume named grid.name: non-zero voxels
// active, the rest background 0. Callers write them (atomically where it matters).
std::string encode_vdb(const DensityGrid& grid);
// Several grids in one file, in order (vdb-export: density and albedo).
std::string encode_vdb(const std::vector<DensityGrid>& grids);

// A fog sphere made the way VFX tools make one: a level-set sphere (OpenVDB createLevelSetSphere)
// converted with sdfToFogVolume, so the interior is 1 (stored as tiles where it can) and density
// falls to 0 over the three voxels inside the surface.
std::string encode_fog_sphere_vdb(double radius, const glm::dvec3& center, double voxel_size,
                                  const std::string& grid_name = "density");

// Built-in sample volumes, made with OpenVDB's own tools (level sets, CSG, fog conversion) because the
// project has no internet to fetch real ones from: what "builtin:NAME[:RESOLUTION]" names in scenes and
// presets, what `brume vdb-sample` writes, what tests and benchmarks convert. Each fits [-1, 1]^3, a
// float fog volume named "density" with `resolution` voxels across those two units.
struct SampleVolumeInfo {
    const char* name;
    const char* description;
};
inline constexpr int kMinSampleResolution = 8;
// A grid is read only when its voxels are at least this large and its box lies within kMaxCoordinate
// (sim/scene_file.h) of the origin, the range scene files accept: beyond it squared distances overflow the
// renderer's floats (a voxel of 1e20 rendered every pixel NaN), below it radii underflow. (OpenVDB itself
// refuses to write voxels much under 1e-5, whose transform's determinant it treats as zero.)
inline constexpr double kMinVoxelSize = 1e-6;
inline constexpr int kMaxSampleResolution = 512;  // 512^3 dense floats: 0.5 GiB
std::span<const SampleVolumeInfo> sample_volumes();
bool is_sample_volume(const std::string& name);
// The built-in names joined by ", ", for the messages that list them.
std::string sample_volume_names();
// Throws VdbError for an unknown name (listing the known ones) or a resolution out of range.
std::string encode_sample_volume_vdb(const std::string& name, int resolution);

// Well-formed files that read_density_grid must refuse, for the tests of its checks.
enum class RefusedVdbSample {
    vector_grid,       // "density" holds vec3s values
    nonuniform_scale,  // voxels of 1 x 2 x 1
    rotated,           // uniform scale, rotated 30 degrees about z
    far_apart,         // two voxels 2e8 apart along x: a sparse grid of two voxels whose dense copy is 800 MB
};
std::string encode_refused_vdb_sample(RefusedVdbSample kind);

}  // namespace brume
