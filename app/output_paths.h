// A run's outputs must not overwrite its inputs or each other (issue 14 item 11): `render s.toml
// --stats s.toml` would replace the scene, `-o X --png X` would keep only the PNG.
#pragma once

#include <filesystem>
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

// The deepest part of `dir` that exists ("." when none does).
std::filesystem::path existing_ancestor(const std::filesystem::path& dir);
// Checks, creating nothing, that the folder `dir` could hold a command's outputs: it is a folder that
// may be written into, or its deepest existing part is. For a command that makes its folder only when
// it has something to write (play's first frame, a benchmark's results after minutes of runs), so that
// a refused or failed run leaves no empty folder and a bad folder is refused before the work. Throws
// std::runtime_error naming `dir` and the reason.
void check_folder_can_be_made(const std::filesystem::path& dir);
// Makes the folder `dir` (and its parents); throws std::runtime_error naming it and the reason.
void make_folder(const std::filesystem::path& dir);

}  // namespace brume::app
