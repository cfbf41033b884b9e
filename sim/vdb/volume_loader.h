// [[vdb]] volumes become spheres here, before anything renders: each VdbVolume's grid is read
// (sim/vdb/density_source.h), converted to the fewest spheres that meet its tolerance
// (sim/vdb/sphere_cloud.h), or fitted (sim/vdb/sphere_fit.h) where the table says fit = true, and placed by
// its transform. Conversions are kept in the conversion cache (sim/vdb/conversion_cache.h). Renderers only
// ever see spheres.
#pragma once

#include "sim/preset.h"
#include "sim/scene.h"
#include "sim/vdb/optical_depth_error.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace brume {

// What converting one volume did, for logs and stats.
struct VolumeReport {
    std::string source;        // density_source_label
    std::size_t spheres = 0;
    std::uint64_t active_voxels = 0;
    OpticalDepthError error;   // measured over the conversion's views (sim/vdb/sphere_cloud.h)
    double seconds = 0.0;      // reading and converting
    bool from_cache = false;   // the spheres came from the conversion cache (sim/vdb/conversion_cache.h)
};

// Appends every scene.volumes entry's spheres to scene.spheres (in table order, after the scene's own
// spheres) and empties scene.volumes. Each conversion meets its tolerance over the axis views, the scene's
// camera and `more_views` (world space). Throws VdbError naming the volume (its index and source) when a
// grid cannot be read, holds no density, or cannot meet its tolerance.
std::vector<VolumeReport> convert_scene_volumes(Scene& scene, const std::vector<Camera>& more_views = {});

// Everything a preset needs before simulating and rendering: convert_scene_volumes on its scene, with
// cameras along its camera path among the views, and load_emitter_densities (sim/vdb/emitter_densities.h).
std::vector<VolumeReport> prepare_preset(Preset& preset);

}  // namespace brume
