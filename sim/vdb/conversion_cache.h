// Converted [[vdb]] volumes kept on disk, so that a render farm's `--frames` jobs, a preview reload or a
// second render of a scene do not convert the same grid again (issue 14: vdb-cloud redid its 2-3.6 s
// conversion on every job; a fit, sim/vdb/sphere_fit.h, takes far longer). docs/vdb.md "The conversion
// cache".
//
// An entry is found by its key: a hash of the grids the conversion reads (their voxel values and
// placement, not the file's name or modification time), every conversion option that can change the
// spheres, and kConversionVersion. It holds the key itself, the spheres and what the conversion measured,
// and a checksum over all of it: an entry that is truncated, corrupt or written for another key reads as
// a miss and is recomputed and replaced. Entries are written atomically (render/atomic_file.h), so jobs
// sharing a cache directory never read a partial one.
//
// The cache is an optimisation and never an error: a missing, unwritable or full cache directory means
// converting as if there were no cache.
#pragma once

#include "sim/density_grid.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/sphere_fit.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace brume {

// Bump whenever a conversion (tiling, sim/vdb/sphere_cloud.cpp and sphere_lattice.cpp; fitting,
// sphere_fit.cpp; the measurement, optical_depth_error.cpp) can give different spheres or figures for the
// same input: every entry written before then becomes a miss.
inline constexpr int kConversionVersion = 4;  // 2: fits merge spheres; 3: a fit stops once it reached its cap;
                                              // 4: a fit stops on jittered held-out views

// Where entries live: $BRUME_CACHE_DIR when set (tests, farms with a shared disk), else
// $XDG_CACHE_HOME/brume/vdb (an absolute XDG_CACHE_HOME only, as the XDG base directory specification
// says), else $HOME/.cache/brume/vdb when HOME is a directory. Empty, meaning no cache, when BRUME_CACHE is
// "off" (or "0", "no", "false") or no directory can be named. Throws std::invalid_argument when BRUME_CACHE
// is neither a word for off nor one for on ("on", "1", "yes", "true").
std::filesystem::path conversion_cache_dir();

// The canonical text of everything that decides a conversion's result: kConversionVersion, a hash of the
// density grid (and the albedo grid, when options has one), and every option but the thread count (the
// conversions give the same spheres on any thread count: TheSameOnAnyThreadCount).
std::string conversion_key(const DensityGrid& grid, const SphereCloudOptions& options, const SphereFitSettings& fit = {});

// The entry for `key` in `dir`, or nothing when there is none or it does not check out (wrong key,
// truncated, checksum mismatch). Never throws.
std::optional<SphereCloud> load_cached_conversion(const std::filesystem::path& dir, const std::string& key);

// Writes the entry for `key` (creating `dir` if needed). False when it could not be written. Never throws.
bool store_cached_conversion(const std::filesystem::path& dir, const std::string& key, const SphereCloud& cloud);

enum class CacheOutcome { Off, Hit, Stored, NotStored };

// The cached cloud for (grid, options) when there is one in conversion_cache_dir(), else convert() stored
// there. `outcome`, when given, says which happened. Exceptions from convert() pass through (failures are
// not cached).
SphereCloud cached_conversion(const DensityGrid& grid, const SphereCloudOptions& options,
                              const std::function<SphereCloud()>& convert, CacheOutcome* outcome = nullptr);

}  // namespace brume
