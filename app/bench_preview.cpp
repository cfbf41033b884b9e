#include "app/bench_preview.h"

#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/preview_command.h"
#include "app/preview_timeline.h"
#include "app/preview_window.h"
#include "render/frame/frame_path.h"
#include "render/methods/fill_ceiling.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/vdb/volume_loader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

struct Row {
    std::string preset;
    PreviewFigures window;
    double headless_internal_ms = 0.0, headless_full_ms = 0.0, fill_full_ms = 0.0;
};

std::vector<std::string> split_names(const std::string& text) {
    std::vector<std::string> out;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t comma = text.find(',', start);
        const std::string name = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!name.empty()) out.push_back(name);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

// Median wall-clock milliseconds of `frames` renders (render and readback), after one warm-up.
double median_render_ms(FramePath& path, GpuMethod& method, const Scene& scene, int frames) {
    path.render(method, scene);
    std::vector<double> ms;
    for (int k = 0; k < frames; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        path.render(method, scene);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

}  // namespace

int run_bench_preview(const BenchArgs& args) {
    // Refused before anything runs: the benchmark is of the window.
    const char* display = std::getenv("DISPLAY");  // GLFW's X11 build, as the preview's (app/preview_window.cpp)
    if (!display || !*display)
        throw PreviewUnavailable("bench preview opens a window: no X11 display: set DISPLAY, or run it "
                                 "under xvfb-run -a -s \"-screen 0 1280x800x24\"");
    int width = 640, height = 360;
    if (!args.size.empty()) parse_size(args.size, width, height);
    const std::vector<std::string> presets =
        args.presets.empty() ? builtin_preset_names() : split_names(args.presets);
    for (const std::string& name : presets)
        if (!builtin_preset(name)) resolve_preset(name);  // names the unknown preset (and the closest)
    const std::string size = std::to_string(width) + "x" + std::to_string(height);

    // The script every preset plays.
    const fs::path script = fs::temp_directory_path() / ("brume-bench-preview-" + std::to_string(::getpid()) + ".script");
    {
        std::ofstream out(script);
        out << "panel on\nplay\nwait " << args.preview_frames << "\nquit\n";
        if (!out) throw std::runtime_error("cannot write " + script.string());
    }
    struct RemoveScript {
        fs::path p;
        ~RemoveScript() {
            std::error_code ignored;
            fs::remove(p, ignored);
        }
    } remove_script{script};

    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    vk::Device device(device_options);
    const char* threads = std::getenv("LP_NUM_THREADS");
    std::printf("# brume bench preview: each preset plays %d frames in a %s window (panel on, adaptive resolution, "
                "target 30 FPS) on %s (LP_NUM_THREADS=%s)\n",
                args.preview_frames, size.c_str(), device.name().c_str(), threads ? threads : "default");
    std::printf("# host: %s\n", host_cpu_description().c_str());
    std::printf("# window figures: mean wall-clock ms of the frames after the internal resolution last changed\n"
                "# competitor: the frame path without a window (brume play's render + readback), median of %d frames,\n"
                "# at the settled internal size and at the full size; ceiling: the fill ceiling at the full size (GPU ms)\n",
                args.frames);
    std::fflush(stdout);

    std::vector<Row> rows;
    for (const std::string& name : presets) {
        Row row;
        row.preset = name;
        PreviewArgs preview;
        preview.preset = name;
        preview.size = size;
        preview.script = script.string();
        preview.device = args.device;
        preview.validate = args.validate;
        const int status = run_preview(preview, &row.window);
        if (status != 0) return status;
        if (row.window.tallied_frames == 0) throw std::runtime_error(name + ": the preview showed no frame");

        // The frame the window showed last, without a window.
        Preset preset = resolve_preset(name);
        preset.scene.camera.width = width;
        preset.scene.camera.height = height;
        for (const VolumeReport& v : prepare_preset(preset)) (void)v;
        PreviewTimeline timeline(preset);
        timeline.seek(row.window.last_frame);
        Scene scene = timeline.scene();
        std::unique_ptr<Method> method = make_method(&device, preset.render.method);
        if (!method->gpu()) throw std::runtime_error(name + ": its method " + preset.render.method + " is not a GPU method");
        FramePath path(device);
        row.headless_full_ms = median_render_ms(path, *method->gpu(), scene, args.frames);
        FillCeiling ceiling(device);
        FrameStats fill;
        path.render(ceiling, scene);
        path.render(ceiling, scene, &fill, false);
        row.fill_full_ms = fill.total_ms;
        scene.camera.width = int(row.window.internal_width);
        scene.camera.height = int(row.window.internal_height);
        row.headless_internal_ms = median_render_ms(path, *method->gpu(), scene, args.frames);
        rows.push_back(row);
    }

    std::printf("\n%-11s %9s %6s %8s %8s %7s %8s %6s %8s | %10s %10s | %8s\n", "preset", "internal", "FPS", "frame_ms",
                "simulate", "upload", "render", "ui", "present", "play@int", "play@full", "fill@full");
    for (const Row& r : rows) {
        const PreviewFigures& w = r.window;
        char internal[24];
        std::snprintf(internal, sizeof internal, "%ux%u", w.internal_width, w.internal_height);
        std::printf("%-11s %9s %6.1f %8.1f %8.2f %7.2f %8.1f %6.2f %8.1f | %10.1f %10.1f | %8.2f\n", r.preset.c_str(),
                    internal, w.fps, w.frame_ms, w.simulate_ms, w.upload_ms, w.render_ms, w.ui_ms, w.present_ms,
                    r.headless_internal_ms, r.headless_full_ms, r.fill_full_ms);
    }
    std::printf("# play@int, play@full: ms a frame of the same frame without a window; the window's render column\n"
                "# should be close to play@int, its frame_ms above it by simulate + upload + ui + present\n");
    return report_validation_messages(device) ? 3 : 0;
}

}  // namespace brume::app
