// `brume preview [PRESET | SCENE.toml]`: the interactive window (docs/preview.md). Its frames go
// through the same simulation, camera and frame path as `brume play`, so a screenshot at the
// viewport's size is the PNG `brume play --size` writes for that frame.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace brume::app {

struct PreviewArgs {
    std::string preset;      // path or built-in name; empty: the default preset
    std::string size;        // the viewport, WxH
    std::string method;      // empty: the preset's
    std::string device;
    std::string max_memory;
    std::string script;      // --script FILE
    std::string screenshot;  // with --frame: save and exit
    long long frame = -1;    // --frame N
    double exposure = 0.0;
    bool exposure_set = false;
    bool validate = false;
    bool fixed_resolution = false;
};

void add_preview_command(CLI::App& app, PreviewArgs& args);
int run_preview(const PreviewArgs& args);

}  // namespace brume::app
