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

// What a scripted run measured, for `brume bench preview`: the frames since the internal resolution
// last changed (the resolution the adaptive mode settled on) and their mean wall-clock milliseconds.
struct PreviewFigures {
    int shown_frames = 0;
    int tallied_frames = 0;
    int last_frame = 0;  // the timeline frame shown last
    unsigned internal_width = 0, internal_height = 0, viewport_width = 0, viewport_height = 0;
    double fps = 0.0;
    double simulate_ms = 0.0, upload_ms = 0.0, render_ms = 0.0, ui_ms = 0.0, present_ms = 0.0, frame_ms = 0.0;
};

void add_preview_command(CLI::App& app, PreviewArgs& args);
// `figures`: filled at the end of a scripted run that showed frames.
int run_preview(const PreviewArgs& args, PreviewFigures* figures = nullptr);

}  // namespace brume::app
