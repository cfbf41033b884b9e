// `brume bench layers`: the full-screen-layers benchmark of Barta & Kovács' Tables 1-2 for ppll, with
// the CPU reference timed on the same frames. `brume bench sim`: milliseconds per simulation step.
// `brume bench vdb` (app/bench_vdb.h): OpenVDB import, spheres against error. `brume bench preview`
// (app/bench_preview.h): the preview window's frame, part by part, for every shipped preset.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace brume::vk {
class Device;
}

namespace brume::app {

struct BenchArgs {
    std::string which = "methods";
    std::string sizes = "800x600,1024x768";
    std::string layers = "2-16:2";
    std::string device;
    int frames = 9;
    std::string spheres = "1000,10000,100000";  // bench scale
    bool no_presets = false;                     // bench scale: skip the shipped presets' table
    std::size_t particles = 100000;  // bench sim
    int steps = 50;                   // bench sim
    int reference_frames = 1;
    bool validate = false;
    bool no_reference = false;
    // bench methods
    std::string output_dir;
    std::string methods;
    std::string scenes = "default,cloud-1000,disjoint-300,layers-8,crossing,plume,fog-bank,explosion";
    std::string size;
    int anim_frames = 16;
    // bench shadows
    std::string shadow_scenes = "default,low-sun,campfire,crossing";
    int shadow_frames = 3;
    // bench vdb
    std::string vdb_sample = "cloud";
    std::string vdb_sizes = "128,256";
    std::string tolerances = "0.02,0.05,0.1,0.2";
    // bench preview
    int preview_frames = 60;
    std::string presets;  // empty: every shipped preset
    // The `bench` subcommand these were parsed by (add_bench_command), so run_bench can ask which
    // options the command line gave; null where a caller fills the fields itself.
    const CLI::App* command = nullptr;
};

void add_bench_command(CLI::App& app, BenchArgs& args);
// The options benchmark WHICH reads (run_bench and the bench_* files), by their first long name;
// empty for an unknown WHICH. The one table behind both `bench WHICH --help` and the refusal below.
const std::vector<std::string>& bench_reads(const std::string& which);
// Refuses, as a UsageError naming the option and the benchmark, an option given on the command line
// that `args.which` does not read: `bench layers --methods kbuf:4` printed ppll's table as if unasked.
void refuse_unread_bench_options(const BenchArgs& args);
// Whether the command line gave option NAME ("--frames"): false without `args.command`.
bool bench_option_given(const BenchArgs& args, const std::string& name);
// `bench WHICH --help` lists only the options WHICH reads: hides the others of `bench` (its
// subcommand) from the help. An unknown WHICH changes nothing (the parser names it).
void restrict_bench_help(CLI::App& bench, const std::string& which);
// Prints the validation messages a bench run collected to stderr; true when there were any (the
// figures then come from a run that broke the API's rules, and the command exits 3).
bool report_validation_messages(vk::Device& device);
int run_bench(const BenchArgs& args);

}  // namespace brume::app
