// `brume render`: one scene, one method, linear EXR and/or PNG, optional JSON statistics.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace brume::app {

struct RenderArgs {
    std::string scene;  // empty: the built-in default scene; or a preset (a built-in's name, or a file)
    int frame = -1;     // --frame: a still of this frame of a preset; -1: not given
    std::string exr;
    std::string png;
    std::string method;  // empty: a preset's [render_settings] method, or auto
    std::string stats;
    std::string size;
    std::string device;
    std::string max_memory;
    std::string shadows;  // empty: the scene's [render] shadow_technique
    std::uint64_t pool_nodes = 0;
    double exposure = 0.0;
    bool exposure_set = false;  // otherwise a preset's own exposure applies
    int repeat = 1;
    int threads = 0;
    bool validate = false;
};

void add_render_command(CLI::App& app, RenderArgs& args);
int run_render(const RenderArgs& args);

}  // namespace brume::app
