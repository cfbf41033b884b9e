#include "app/bench_shadows.h"

#include "app/charts.h"
#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/output_paths.h"
#include "render/atomic_file.h"
#include "render/fast_tracer.h"
#include "render/image_compare.h"
#include "render/methods/fill_ceiling.h"
#include "render/methods/ppll.h"
#include "render/methods/registry.h"
#include "render/methods/tiles.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/builtin_scenes.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

struct ShadowScene {
    std::string name;
    std::vector<Scene> frames;  // one for a static scene, consecutive frames of an animation
};

// The built-in default scene, or `count` consecutive frames of a shipped preset from a third of its
// timeline (emitters have filled the view), at w x h. Shadows on in either case: a scene that has none
// is benchmarked as if it had.
ShadowScene make_shadow_scene(const std::string& name, int count, int w, int h) {
    ShadowScene out{name, {}};
    if (name == "default") {
        Scene s = default_scene();
        s.camera.width = w;
        s.camera.height = h;
        out.frames.push_back(std::move(s));
    } else {
        std::optional<Preset> preset = builtin_preset(name);
        if (!preset)
            throw UsageError("--shadow-scenes: no scene '" + name + "': the scenes are default and the presets (" +
                             builtin_preset_list() + ")");
        prepare_preset(*preset);
        Simulator sim(*preset);
        sim.advance_to_frame(std::max(0, std::min(preset->timeline.frame_count() / 3, preset->timeline.frame_count() - count)));
        for (int f = 0; f < count; ++f) {
            if (f > 0) sim.step_frame();
            Scene s = preset->scene;
            sim.append_spheres(s.spheres);
            s.camera = camera_at(*preset, sim.time());
            s.camera.width = w;
            s.camera.height = h;
            out.frames.push_back(std::move(s));
        }
    }
    for (Scene& s : out.frames) s.lighting.shadows = true;
    return out;
}

// Mean and 99.9th percentile of |image - reference| over the reference's peak, pixels and channels
// together (the terms docs/accuracy.md states the techniques' error in).
void error_over_peak(const Image& img, const Image& ref, double& mean, double& p999) {
    double peak = 0.0;
    for (float v : ref.rgb) peak = std::max(peak, double(v));
    if (peak <= 0.0) peak = 1.0;
    std::vector<double> e(img.rgb.size());
    double sum = 0.0;
    for (std::size_t k = 0; k < e.size(); ++k) {
        e[k] = std::abs(double(img.rgb[k]) - double(ref.rgb[k])) / peak;
        sum += e[k];
    }
    std::sort(e.begin(), e.end());
    mean = e.empty() ? 0.0 : sum / double(e.size());
    p999 = e.empty() ? 0.0 : e[std::min(e.size() - 1, std::size_t(0.999 * double(e.size())))];
}

struct Technique {
    const char* name;
    bool shadows;
    ShadowTechnique technique;
};
constexpr Technique kTechniques[] = {
    {"none", false, ShadowTechnique::Accurate},
    {"per-sphere", true, ShadowTechnique::PerSphere},
    {"accurate", true, ShadowTechnique::Accurate},
};

// The shadowed frame's exact paths: ppll and tiles on the device (tiles is what auto takes on a GPU),
// and trace on the CPU (what auto takes on a CPU device). tiles shares ppll's integrator and its
// accurate technique; trace has its own (docs/accuracy.md).
constexpr const char* kMethods[] = {"ppll", "tiles", "trace"};  // the default of --methods, and what it may name

struct Result {
    std::string scene, method, technique;
    double ms = 0.0, mean = 0.0, p999 = 0.0, temporal = 0.0;
};

double wall_ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_bench_shadows(const BenchArgs& args) {
    int w = 128, h = 96;
    if (!args.size.empty()) parse_size(args.size, w, h);
    std::vector<std::string> names;
    {
        std::stringstream in(args.shadow_scenes);
        for (std::string item; std::getline(in, item, ',');)
            if (!item.empty()) names.push_back(item);
    }
    if (names.empty()) throw std::invalid_argument("--shadow-scenes: no scene named");
    if (args.no_reference && !args.output_dir.empty())
        throw UsageError("--output: the chart plots each technique's error against the reference, which --no-reference skips");
    if (!args.output_dir.empty()) check_folder_can_be_made(args.output_dir);  // made when the figures are in
    std::vector<std::string> methods(std::begin(kMethods), std::end(kMethods));
    if (!args.methods.empty()) methods = split_method_list(args.methods);
    if (methods.empty()) throw UsageError("--methods: no method named (bench shadows compares ppll, tiles and trace)");
    for (const std::string& m : methods)
        if (std::find(std::begin(kMethods), std::end(kMethods), m) == std::end(kMethods))
            throw UsageError("--methods: bench shadows compares ppll, tiles and trace (got '" + m + "')");
    std::vector<ShadowScene> scenes;
    for (const std::string& name : names) scenes.push_back(make_shadow_scene(name, args.shadow_frames, w, h));

    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    vk::Device device(device_options);
    PpllMethod ppll(device);
    TilesMethod tiles(device);
    FillCeiling fill(device);
    const double warm_ms = warm_up_ms(device.properties().deviceType);  // for the GPU's rows
    const char* threads = std::getenv("LP_NUM_THREADS");
    std::printf("# brume bench shadows: the shadow techniques of ppll and tiles (GPU ms on %s, LP_NUM_THREADS=%s) and of trace "
                "(CPU wall-clock ms, every usable core, %s code) at %dx%d; the mean over a scene's frames of the median of %d "
                "rounds, each round rendering every technique in turn (twice, the second timed), after a warm-up of 1 render "
                "(and %.0f ms on the GPU)\n",
                device.name().c_str(), threads ? threads : "default", fast_trace_instructions(), w, h, args.frames,
                warm_ms);
    std::printf("# host: %s\n", host_cpu_description().c_str());
    if (args.no_reference)
        std::printf("# --no-reference: no error columns and no competitor\n");
    else
        std::printf("# error against the exact CPU reference (double, adaptive quadrature between the shadow edges), over "
                    "its peak: mean and p99.9 of |image - ref| (worst frame), temporal = the largest popping metric over "
                    "frame steps\n");
    std::printf("# ceiling: x_none = the median over the rounds of ms / the same round's frame without shadows (the issue's "
                "bound for accurate: 2x); competitor: vs_ref = reference ms / ms; fill_ms = rasterising the impostors alone\n");
    std::printf("%-11s %6s  %-6s %-10s %9s %7s %9s %9s %9s %9s %8s  %s\n", "scene", "frames", "method", "technique", "ms",
                "x_none", "mean/pk", "p99.9/pk", "temporal", "fill_ms", "vs_ref", "passes (ms, last frame)");

    std::vector<Result> results;
    for (const ShadowScene& scene : scenes) {
        // The exact reference once per frame, timed (wall clock, all cores).
        std::vector<Image> refs;
        std::vector<double> ref_ms;
        if (!args.no_reference)
            for (const Scene& s : scene.frames) {
                const auto t0 = std::chrono::steady_clock::now();
                refs.push_back(render_reference(s));
                ref_ms.push_back(wall_ms_since(t0));
            }
        const double reference_ms = refs.empty() ? 0.0 : median(ref_ms);
        std::vector<double> fill_ms;
        warm_up([&] { fill.render(scene.frames[0], nullptr); }, warm_ms);
        for (int r = 0; r < args.frames; ++r) {
            FrameStats stats;
            fill.render(scene.frames[0], &stats);
            fill_ms.push_back(stats.total_ms);
        }
        const double fill_median = median(fill_ms);

        // trace keeps its memory (the sun map) from render to render, as the frame path's does for a
        // user's frames: allocated afresh each render, the map's pages faulted in again every frame
        // (and past glibc's largest heap block, 32 MiB, that is every allocation).
        FastTraceScratch trace_scratch;
        FastTraceOptions trace_options;
        trace_options.scratch = &trace_scratch;
        for (const std::string& name : methods) {
            const char* method = name.c_str();
            const bool on_cpu = std::string(method) == "trace";
            GpuMethod& gpu = std::string(method) == "tiles" ? static_cast<GpuMethod&>(tiles) : ppll;
            constexpr std::size_t kCount = std::size(kTechniques);
            // Per technique: its row, its last frame's image (the temporal error's), the sum over the
            // frames of its median ms and of its median ratio to the frame without shadows, and whether
            // the device refused it (and why).
            std::array<Result, kCount> rows;
            std::array<Image, kCount> previous;
            std::array<double, kCount> ms_sum{}, ratio_sum{};
            std::array<std::string, kCount> refused, passes;
            for (std::size_t t = 0; t < kCount; ++t) rows[t] = Result{scene.name, method, kTechniques[t].name};
            const auto render = [&](const Scene& s, FrameStats* stats) {
                return on_cpu ? render_fast_trace(s, trace_options) : gpu.render(s, stats);
            };
            for (std::size_t f = 0; f < scene.frames.size(); ++f) {
                std::array<Scene, kCount> variants;
                for (std::size_t t = 0; t < kCount; ++t) {
                    variants[t] = scene.frames[f];
                    variants[t].lighting.shadows = kTechniques[t].shadows;
                    variants[t].render.shadow_technique = kTechniques[t].technique;
                }
                // Warm-up: the first frame of a pipeline compiles it (and trace's touches its memory).
                // A frame whose resolve exceeds the device's loop budget is refused by name (ppll.h);
                // the row says so instead of a figure.
                std::array<Image, kCount> images;
                for (std::size_t t = 0; t < kCount; ++t) {
                    if (!refused[t].empty()) continue;
                    try {
                        warm_up([&] { images[t] = render(variants[t], nullptr); }, on_cpu ? 0.0 : warm_ms);
                    } catch (const ListResolveError& e) {
                        refused[t] = e.what();
                    }
                }
                // The techniques in turn, round after round, each round's ratios to its own frame
                // without shadows: on a shared machine whose speed drifts by 1.5x and more over
                // seconds, techniques timed one after another (each for all its renders) gave ratios
                // that moved as much as the drift. Each turn renders its technique once untimed: on
                // lavapipe ppll's first frame after a change of technique took up to 2x its time
                // (campfire at 128x96: the frame without shadows after an accurate one, 14-48 ms
                // against 9-12).
                std::array<std::vector<double>, kCount> ms, ratio;
                FrameStats stats;
                for (int r = 0; r < args.frames; ++r)
                    for (std::size_t t = 0; t < kCount; ++t) {
                        if (!refused[t].empty()) continue;
                        try {
                            images[t] = render(variants[t], nullptr);
                            if (on_cpu) {
                                const auto t0 = std::chrono::steady_clock::now();
                                images[t] = render(variants[t], nullptr);
                                ms[t].push_back(wall_ms_since(t0));
                            } else {
                                images[t] = render(variants[t], &stats);
                                ms[t].push_back(stats.total_ms);
                                if (f + 1 == scene.frames.size() && r + 1 == args.frames) {
                                    std::ostringstream text;
                                    for (const PassTime& p : stats.passes) {
                                        char cell[64];
                                        std::snprintf(cell, sizeof cell, " %s=%.1f", p.name.c_str(), p.ms);
                                        text << cell;
                                    }
                                    passes[t] = text.str();
                                }
                            }
                            if (refused[0].empty()) ratio[t].push_back(ms[t].back() / ms[0].back());
                        } catch (const ListResolveError& e) {
                            refused[t] = e.what();
                        }
                    }
                for (std::size_t t = 0; t < kCount; ++t) {
                    if (!refused[t].empty()) continue;
                    ms_sum[t] += median(ms[t]);
                    if (!ratio[t].empty()) ratio_sum[t] += median(ratio[t]);
                    if (!refs.empty()) {
                        double mean = 0.0, p999 = 0.0;
                        error_over_peak(images[t], refs[f], mean, p999);
                        rows[t].mean = std::max(rows[t].mean, mean);
                        rows[t].p999 = std::max(rows[t].p999, p999);
                        if (f > 0)
                            rows[t].temporal = std::max(rows[t].temporal,
                                                        temporal_error(images[t], previous[t], refs[f], refs[f - 1]));
                    }
                    previous[t] = std::move(images[t]);
                }
            }
            for (std::size_t t = 0; t < kCount; ++t) {
                Result& res = rows[t];
                if (!refused[t].empty()) {
                    std::printf("%-11s %6zu  %-6s %-10s refused on this device: %.90s...\n", scene.name.c_str(),
                                scene.frames.size(), method, res.technique.c_str(), refused[t].c_str());
                    continue;
                }
                const double frames = double(scene.frames.size());
                res.ms = ms_sum[t] / frames;
                char temporal[32] = "-", mean[32] = "-", p999[32] = "-", x_none[32] = "-", vs_ref[32] = "-";
                if (scene.frames.size() > 1 && !refs.empty()) std::snprintf(temporal, sizeof temporal, "%.2e", res.temporal);
                if (!refs.empty()) {
                    std::snprintf(mean, sizeof mean, "%.2e", res.mean);
                    std::snprintf(p999, sizeof p999, "%.2e", res.p999);
                    std::snprintf(vs_ref, sizeof vs_ref, "%.1fx", reference_ms / res.ms);
                }
                if (refused[0].empty()) std::snprintf(x_none, sizeof x_none, "%.2fx", ratio_sum[t] / frames);
                std::printf("%-11s %6zu  %-6s %-10s %9.2f %7s %9s %9s %9s %9.2f %8s %s\n", scene.name.c_str(),
                            scene.frames.size(), method, res.technique.c_str(), res.ms, x_none, mean, p999, temporal,
                            fill_median, vs_ref, on_cpu ? "(CPU)" : passes[t].c_str());
                if (!refs.empty()) results.push_back(res);
            }
        }
        if (refs.empty()) {
            std::fflush(stdout);
            continue;
        }
        std::printf("%-11s %6zu  %-6s %-10s %9.2f %7s %9s %9s %9s %9.2f %7.1fx (CPU, wall clock, all cores)\n",
                    scene.name.c_str(), scene.frames.size(), "-", "reference", reference_ms, "-", "0", "0", "0",
                    fill_median, 1.0);
        std::fflush(stdout);
    }

    if (!args.output_dir.empty()) {
        const fs::path dir(args.output_dir);
        make_folder(dir);
        std::ostringstream data;
        data << "# series scene ms mean_error_over_peak p999_error_over_peak temporal\n";
        std::ostringstream plot;
        plot << "set terminal svg size 880,440\nset output 'shadows.svg'\nset logscale xy\nset key outside right top\n"
             << "set xlabel 'ms per frame (ppll, tiles: GPU; trace: CPU wall clock)'\nset ylabel 'mean |error| / peak against the exact reference'\n"
             << "set title 'brume bench shadows: " << w << "x" << h << ", " << device.name() << "'\nplot ";
        int index = 0;
        for (const std::string& method : methods)
            for (const Technique& t : kTechniques) {
                const std::string series = std::string(method) + "-" + t.name;
                data << "\n\n# " << series << "\n";
                for (const Result& r : results)
                    if (r.method == method && r.technique == t.name)
                        // Log axes: an error of exactly 0 is drawn at 1e-9.
                        data << series << " " << r.scene << " " << r.ms << " " << std::max(r.mean, 1e-9) << " "
                             << r.p999 << " " << r.temporal << "\n";
                plot << (index ? ", " : "") << "'shadows.dat' index " << index
                     << " using 3:4 with points pointsize 1.5 title '" << series << "', '' index " << index
                     << " using 3:4:2 with labels offset 0,1 font ',8' notitle";
                ++index;
            }
        plot << "\nset terminal pngcairo size 880,440\nset output 'shadows.png'\nreplot\n";
        write_file_atomically(dir / "shadows.dat", data.str());
        for (const std::string& file : draw_charts(dir, {{"shadows", plot.str()}})) std::printf("# chart: %s\n", file.c_str());
    }
    return report_validation_messages(device) ? 3 : 0;
}

}  // namespace brume::app
