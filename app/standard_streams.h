// "-" for a file names a standard stream, as in most command-line tools (docs/decisions.md, "Outputs").
//
// Outputs named "-" go to standard output (render/atomic_file.h), so that
// `brume render scene.toml --stats - | jq .gpu_ms` and `brume vdb-export p.toml -o - | ssh host ...` work
// as they do with other tools. Standard output then carries that output's bytes and nothing else: the
// command's own lines (the timing, "wrote ...", notes) go to standard error instead.
#pragma once

#include <string>

namespace brume::app {

// Called once a command has checked its outputs (check_outputs_distinct allows one "-" a run) and
// before it prints anything, for the output named "-": `option` as the user gave it, `binary` for
// image and grid bytes. Keeps the process's standard output for that output alone and points
// everything else printed there at standard error. Throws UsageError when a binary output would go
// to a terminal, and FileWriteError when standard output is closed.
void claim_standard_output(const std::string& option, bool binary);

// "-" when `path` names the file standard output is open on (/dev/stdout, /proc/self/fd/1, or the
// file `> FILE` opened) and that is a pipe, socket or regular file; else `path`. An output written
// there is then written as "-" is: its bytes alone on standard output, the command's lines on standard
// error (`render --stats /dev/stdout | jq` would otherwise read "wrote ..." after the JSON). A terminal
// or a device (/dev/null) is left as named. Called on each output path before any is checked.
std::string standard_output_alias(const std::string& path);

// The name that stands for standard input, as "-" stands for standard output among the outputs.
inline constexpr const char* kStandardInputName = "-";

// The path to read for an input that may be "-", standard input: `render -` and `play -` read the
// scene or preset a program writes into the pipe (`gen_scene.py | brume render - --png out.png`); its
// relative paths ([[vdb]] files) are taken from the working directory.
std::string input_path(const std::string& given);

// How messages name an output: "standard output" for "-", else the path.
std::string shown_output_name(const std::string& path);

// For an output that cannot be a stream (play's folder of frames, a video, a screenshot, a
// benchmark's folder): throws UsageError when `path` is "-", naming `option` and saying what it needs.
void refuse_standard_output(const std::string& option, const std::string& path, const std::string& what);

}  // namespace brume::app
