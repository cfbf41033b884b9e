// A run's outputs must not overwrite its inputs or each other (issue 14 item 11): `render s.toml
// --stats s.toml` would replace the scene, `-o X --png X` would keep only the PNG.
#pragma once

#include <string>
#include <vector>

namespace brume::app {

struct NamedPath {
    std::string option;  // how the user gave it: "-o", "--png", "the scene"
    std::string path;
};

// Throws std::invalid_argument when two outputs reach the same file (through links too), or an
// output reaches an input. Two outputs into the same character device (/dev/null) are allowed:
// nothing is replaced there. Empty paths are skipped (not given). At most one output may be "-",
// standard output (app/standard_streams.h).
void check_outputs_distinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

}  // namespace brume::app
