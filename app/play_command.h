// `brume play`: simulate a preset and render its frames to an image sequence (and a video).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace brume::app {

struct PlayArgs {
    std::string preset;  // path or built-in name; empty: the default preset
    std::string output_dir;
    std::string frames;  // "A-B" or "N", 0-based and inclusive; empty: all
    std::string formats = "png";
    std::string video;
    std::string size;
    std::string method;  // empty: the preset's
    std::string device;
    std::string max_memory;
    int threads = 0;  // CPU threads for the CPU tracers (0: every usable CPU)
    double exposure = 0.0;
    bool exposure_set = false;
    bool list = false;
    bool validate = false;
};

void add_play_command(CLI::App& app, PlayArgs& args);
int run_play(const PlayArgs& args);

}  // namespace brume::app
