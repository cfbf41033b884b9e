#include "app/bench_methods.h"

#include "app/charts.h"
#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/output_paths.h"
#include "render/atomic_file.h"
#include "render/image_compare.h"
#include "render/methods/registry.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/builtin_scenes.h"
#include "sim/camera_path.h"
#include "sim/layers_scene.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

// Timed frames of a static scene when --frames is not given: its median, against one frame's noise on a
// shared machine, at a cost beside the reference's and the animated presets' frames.
constexpr int kStaticFrames = 5;
// A depth bin of the error chart with fewer pixels than this is noise, not a mean, and is left out.
constexpr int kMinDepthBinPixels = 20;

// One scene of the chart: a static scene (one frame) or consecutive frames of a preset.
struct BenchScene {
    std::string name;
    std::vector<Scene> frames;
};

Scene cloud_scene(int count, int width, int height) {
    Scene s;
    s.source = "cloud-" + std::to_string(count);
    s.camera.position = {0.3, 1.2, 7.0};
    s.camera.look_at = {0.0, 0.2, 0.0};
    s.camera.width = width;
    s.camera.height = height;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < count; ++i) {
        Sphere sp;
        sp.center = {u(rng) * 4 - 2, u(rng) * 3 - 1, u(rng) * 4 - 2};
        sp.radius = 0.1 + 0.5 * u(rng);
        sp.extinction = std::pow(10.0, u(rng) * 2.5 - 2.0);
        sp.albedo = {u(rng), u(rng), u(rng)};
        s.spheres.push_back(sp);
    }
    s.boxes.push_back(Box{{-5, -1.5, -5}, {5, -1, 5}, {0.3, 0.3, 0.3}});
    return s;
}

// Spheres that never share volume (snow, sparse dust): where `auto` needs no per-pixel lists.
Scene disjoint_scene(int count, int width, int height) {
    Scene s = cloud_scene(0, width, height);
    s.source = "disjoint-" + std::to_string(count);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int attempts = 0; int(s.spheres.size()) < count && attempts < 100 * count; ++attempts) {
        Sphere sp;
        sp.center = {u(rng) * 5 - 2.5, u(rng) * 3.5 - 1, u(rng) * 5 - 2.5};
        sp.radius = 0.05 + 0.2 * u(rng);
        sp.extinction = 0.5 + 4.0 * u(rng);
        sp.albedo = {0.7 + 0.3 * u(rng), 0.7 + 0.3 * u(rng), 0.8 + 0.2 * u(rng)};
        bool clear = true;
        for (const Sphere& o : s.spheres)
            if (glm::length(o.center - sp.center) < o.radius + sp.radius) clear = false;
        if (clear) s.spheres.push_back(sp);
    }
    s.render.min_transmittance = 0.0;
    return s;
}

BenchScene preset_frames(const std::string& name, int frames, int width, int height) {
    std::optional<Preset> preset = builtin_preset(name);
    if (!preset) throw std::invalid_argument("no built-in preset '" + name + "'");
    prepare_preset(*preset);
    BenchScene out{name, {}};
    Simulator sim(*preset);
    // Start a quarter in, where emitters have filled the view, and take consecutive frames.
    const int first = std::max(0, std::min(preset->timeline.frame_count() / 4, preset->timeline.frame_count() - frames));
    sim.advance_to_frame(first);
    for (int f = 0; f < frames; ++f) {
        if (f > 0) sim.step_frame();
        Scene scene = preset->scene;
        sim.append_spheres(scene.spheres);
        scene.camera = camera_at(*preset, sim.time());
        scene.camera.width = width;
        scene.camera.height = height;
        out.frames.push_back(std::move(scene));
    }
    return out;
}

std::vector<BenchScene> make_scenes(const std::vector<std::string>& names, int frames, int w, int h) {
    std::vector<BenchScene> scenes;
    for (const std::string& name : names) {
        if (name == "default") {
            Scene s = default_scene();
            s.camera.width = w;
            s.camera.height = h;
            scenes.push_back({name, {s}});
        } else if (name == "cloud-1000") {
            scenes.push_back({name, {cloud_scene(1000, w, h)}});
        } else if (name == "disjoint-300") {
            scenes.push_back({name, {disjoint_scene(300, w, h)}});
        } else if (name == "layers-8") {
            scenes.push_back({name, {make_layers_scene(8, w, h)}});
        } else if (builtin_preset_toml(name)) {
            scenes.push_back(preset_frames(name, frames, w, h));
        } else {
            throw UsageError("--scenes: no scene '" + name + "': the scenes are default, cloud-1000, disjoint-300, "
                             "layers-8 and the presets (" + builtin_preset_list() + ")");
        }
    }
    // Shadowed scenes by the per-sphere technique, the comparison methods' light term, for every method
    // (ppll is exact for it): the chart compares ordering and blending, not light models.
    for (BenchScene& scene : scenes)
        for (Scene& frame : scene.frames)
            if (frame.lighting.shadows) frame.render.shadow_technique = ShadowTechnique::PerSphere;
    return scenes;
}


struct Row {
    std::string method, scene;
    bool exact = false;
    int frames = 0;              // frames timed: a static scene's repeats, or an animation's frames
    std::uint64_t memory_bytes = 0;  // the most any frame of this scene held, by a method made for it
    double median_ms = 0, rmse = 0, psnr_db = 0, max_error = 0, temporal_mean = 0, temporal_max = 0;
    std::vector<double> temporal;  // per frame step
};

std::string short_bytes(std::uint64_t count) {
    const double bytes = double(count);
    char text[32];
    if (bytes >= 1024.0 * 1024.0) std::snprintf(text, sizeof text, "%.1f MiB", bytes / (1024.0 * 1024.0));
    else if (bytes >= 1024.0) std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
    else std::snprintf(text, sizeof text, "%.0f B", bytes);
    return text;
}

// RFC 4180 quoting: method names such as "stochastic:8,depth" hold commas.
std::string csv_text(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string number(double v) {
    if (!std::isfinite(v)) return v > 0 ? "\"inf\"" : "null";
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

}  // namespace

void add_bench_methods_options(CLI::App& cmd, BenchArgs& args) {
    cmd.add_option("-o,--output", args.output_dir,
                   "bench methods (default bench/), scale, shadows and vdb: folder for results and charts");
    cmd.add_option("--methods", args.methods,
                   "bench methods and scale: comma-separated specs (default: all, with settings sweeps; a setting "
                   "that holds a comma stays whole: stochastic:8,depth,ppll is two); bench shadows: some of ppll, "
                   "tiles, trace");
    cmd.add_option("--scenes", args.scenes, "bench methods: comma-separated scenes/presets")->capture_default_str();
    cmd.add_option("--size", args.size,
                   "resolution WxH: bench methods (default 160x120), scale (640x360), shadows (128x96), preview (the "
                   "window, 640x360)");
    cmd.add_option("--anim-frames", args.anim_frames, "bench methods: consecutive frames per animated preset")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();
}

int run_bench_methods(const BenchArgs& args) {
    int w = 160, h = 120;
    if (!args.size.empty()) parse_size(args.size, w, h);
    // A bad spec is refused before the output folder is made or the device opened.
    // A static scene is timed over several frames (--frames), an animated one over its frames.
    const int static_frames = bench_option_given(args, "--frames") ? args.frames : kStaticFrames;
    const std::vector<std::string> specs = args.methods.empty() ? bench_method_specs() : split_method_list(args.methods);
    if (specs.empty()) throw UsageError("--methods: no method named (brume methods lists them)");  // "," ran none
    for (const std::string& spec : specs) check_method_usage(spec, 0);
    // So is a scene name (the scenes are made first: a bad one leaves no empty folder behind).
    const std::vector<BenchScene> scenes = make_scenes(split_commas(args.scenes), args.anim_frames, w, h);
    const fs::path dir = args.output_dir.empty() ? fs::path("bench") : fs::path(args.output_dir);
    check_folder_can_be_made(dir);

    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    vk::Device device(device_options);
    // Build every method first, so that a method the device refuses fails before any work.
    std::vector<std::unique_ptr<Method>> methods;
    for (const std::string& spec : specs) methods.push_back(make_method(&device, spec));
    // The folder once the device and every method are there: a missing device leaves none behind.
    make_folder(dir);
    check_writable_path(dir / "results.csv");

    std::printf("# brume bench: %zu methods x %zu scenes at %dx%d on %s; errors against the CPU reference\n",
                methods.size(), scenes.size(), w, h, device.name().c_str());
    std::printf("# ms: the median of %d frames of a static scene, of every frame of an animated one (%d), after an "
                "untimed frame; memory: the most a frame held, each scene by a method made for it\n",
                static_frames, args.anim_frames);
    std::printf("# host: %s\n", host_cpu_description().c_str());
    // The method column as wide as the longest name: "stochastic:8,depth" pushed its row out of line.
    int name_width = 16;
    for (const std::unique_ptr<Method>& method : methods) name_width = std::max(name_width, int(method->name().size()));
    std::printf("%-*s %-12s %9s %12s %10s %9s %10s %11s %11s\n", name_width, "method", "scene", "ms", "memory",
                "rmse/peak", "psnr_db", "max/peak", "temporal", "temp_max");

    std::vector<Row> rows;
    std::map<std::string, std::map<std::uint32_t, std::pair<double, double>>> depth_error;  // method -> n -> (sum, count)
    for (const BenchScene& scene : scenes) {
        // Reference frames once per scene; every method is compared with the same images.
        std::vector<Image> refs;
        // Shadowed scenes against the reference's per-sphere mode (make_scenes; bench shadows charts the
        // shadow techniques against the exact model).
        for (const Scene& s : scene.frames) {
            ReferenceOptions options;
            if (s.lighting.shadows) options.shadows = ReferenceShadows::PerSphere;
            refs.push_back(render_reference(s, options));
        }
        std::vector<std::uint32_t> complexity;
        if (scene.frames.size() == 1) complexity = reference_list_lengths(scene.frames[0]);

        const bool still = scene.frames.size() == 1;
        for (std::size_t m = 0; m < methods.size(); ++m) {
            // A method made for each scene: ppll's node pool, grown on cloud-1000, was reported as the
            // memory of every later scene (disjoint-300: 57 KiB alone, 895 KiB after the cloud). The
            // methods made before the first scene were the check that the device takes them all.
            if (&scene != &scenes.front()) {
                methods[m].reset();
                methods[m] = make_method(&device, specs[m]);
            }
            Method& method = *methods[m];
            Row row;
            row.method = method.name();
            row.scene = scene.name;
            row.exact = method.exact();
            std::vector<double> ms;
            Image prev;
            double rmse_sum = 0, psnr_sum = 0;
            FrameStats stats;
            // An untimed first frame: shader compilation and first-touch memory are not the method's cost.
            method.render(scene.frames[0], nullptr);
            const int timed = still ? static_frames : int(scene.frames.size());
            for (int t = 0; t < timed; ++t) {
                const std::size_t f = still ? 0 : std::size_t(t);
                const Image img = method.render(scene.frames[f], &stats);
                ms.push_back(stats.total_ms);
                row.memory_bytes = std::max<std::uint64_t>(row.memory_bytes, stats.memory_bytes);
                // A static scene's repeats are for its time: its error is measured once, on the last.
                if (still && t + 1 < timed) continue;
                const ImageDiff d = compare_images(img, refs[f], 0.0);
                rmse_sum += d.peak > 0 ? d.rmse / d.peak : d.rmse;
                psnr_sum += std::isfinite(d.psnr_db) ? d.psnr_db : 200.0;
                row.max_error = std::max(row.max_error, d.peak > 0 ? d.max_abs / d.peak : d.max_abs);
                if (f > 0) row.temporal.push_back(temporal_error(img, prev, refs[f], refs[f - 1]));
                if (!complexity.empty()) {
                    double peak = d.peak > 0 ? d.peak : 1.0;
                    for (std::size_t p = 0; p < complexity.size(); ++p) {
                        double e = 0;
                        for (int c = 0; c < 3; ++c) e += std::abs(double(img.rgb[p * 3 + c]) - refs[f].rgb[p * 3 + c]);
                        auto& bin = depth_error[row.method][complexity[p]];
                        bin.first += e / 3.0 / peak;
                        bin.second += 1;
                    }
                }
                prev = img;
            }
            row.frames = timed;
            row.median_ms = median(ms);
            row.rmse = rmse_sum / double(scene.frames.size());
            row.psnr_db = psnr_sum / double(scene.frames.size());
            if (!row.temporal.empty()) {
                for (double t : row.temporal) {
                    row.temporal_mean += t / double(row.temporal.size());
                    row.temporal_max = std::max(row.temporal_max, t);
                }
            }
            std::printf("%-*s %-12s %9.2f %12s %10.2e %9.1f %10.2e %11s %11s\n", name_width, row.method.c_str(), row.scene.c_str(),
                        row.median_ms, short_bytes(row.memory_bytes).c_str(), row.rmse, row.psnr_db, row.max_error,
                        row.temporal.empty() ? "-" : number(row.temporal_mean).c_str(),
                        row.temporal.empty() ? "-" : number(row.temporal_max).c_str());
            std::fflush(stdout);
            rows.push_back(std::move(row));
        }
    }
    if (report_validation_messages(device)) return 3;

    // results.csv / results.json
    std::ostringstream csv, json;
    csv << "method,scene,exact,frames,median_gpu_ms,memory_bytes,rmse_over_peak,psnr_db,max_error_over_peak,"
           "temporal_error_mean,temporal_error_max\n";
    json << "{\n  \"device\": " << json_string(device.name()) << ",\n  \"host\": " << json_string(host_cpu_description())
         << ",\n  \"width\": " << w << ",\n  \"height\": " << h
         << ",\n  \"results\": [\n";
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const Row& r = rows[k];
        csv << csv_text(r.method) << ',' << csv_text(r.scene) << ',' << (r.exact ? 1 : 0) << ',' << r.frames << ',' << number(r.median_ms)
            << ',' << r.memory_bytes << ',' << number(r.rmse) << ',' << number(r.psnr_db) << ','
            << number(r.max_error) << ',' << (r.temporal.empty() ? "" : number(r.temporal_mean)) << ','
            << (r.temporal.empty() ? "" : number(r.temporal_max)) << '\n';
        json << "    {\"method\": " << json_string(r.method) << ", \"scene\": " << json_string(r.scene)
             << ", \"exact\": " << (r.exact ? "true" : "false") << ", \"frames\": " << r.frames
             << ", \"median_gpu_ms\": " << number(r.median_ms) << ", \"memory_bytes\": " << r.memory_bytes
             << ", \"rmse_over_peak\": " << number(r.rmse) << ", \"psnr_db\": " << number(r.psnr_db)
             << ", \"max_error_over_peak\": " << number(r.max_error) << ", \"temporal_error\": [";
        for (std::size_t t = 0; t < r.temporal.size(); ++t) json << (t ? ", " : "") << number(r.temporal[t]);
        json << "]}" << (k + 1 < rows.size() ? "," : "") << "\n";
    }
    json << "  ]\n}\n";
    write_file_atomically(dir / "results.csv", csv.str());
    write_file_atomically(dir / "results.json", json.str());

    // Chart data: one point per method (mean over scenes), temporal series, error by depth complexity.
    std::vector<ChartPoint> points;
    for (const std::unique_ptr<Method>& method : methods) {
        ChartPoint p{method->name(), 0, 0, method->exact()};
        int n = 0;
        for (const Row& r : rows)
            if (r.method == method->name()) {
                p.ms += std::log(std::max(r.median_ms, 1e-3));
                p.error += r.rmse;
                ++n;
            }
        p.ms = std::exp(p.ms / n);  // geometric mean: scenes differ in cost by orders of magnitude
        p.error /= n;
        points.push_back(p);
    }
    std::vector<TemporalSeries> series;
    for (const Row& r : rows)
        if (!r.temporal.empty()) series.push_back({r.scene, r.method, r.temporal});
    std::vector<DepthErrorSeries> depth;
    for (const auto& [name, bins] : depth_error) {
        DepthErrorSeries d{name, {}};
        for (const auto& [n, acc] : bins)
            if (acc.second >= kMinDepthBinPixels) d.points.push_back({double(n), acc.first / acc.second});
        if (!d.points.empty()) depth.push_back(std::move(d));
    }
    // At 2x2 no list length is met by enough pixels to mean anything: the chart is not drawn, and said so.
    if (!depth_error.empty() && depth.empty())
        std::fprintf(stderr, "brume: error_vs_depth not charted: at %dx%d no list length is met by %d pixels of the "
                             "static scenes (a larger --size charts it)\n", w, h, kMinDepthBinPixels);
    const ChartsWritten charts = write_charts(dir, points, series, depth);
    for (const std::string& c : charts.drawn) std::printf("wrote %s\n", c.c_str());
    std::printf("wrote %s and %s\n", (dir / "results.csv").c_str(), (dir / "results.json").c_str());
    // The charts this bench may make that this run did not (README, "Methods compared"): an earlier run's
    // temporal_crossing.svg beside a static-only run's results read as this run's.
    std::vector<std::string> known = {"speed_accuracy", "error_vs_depth"};
    for (const std::string& name : builtin_preset_names()) known.push_back("temporal_" + name);
    for (const std::string& r : remove_charts_not_written(dir, known, charts.stems))
        std::printf("removed %s (an earlier run's chart, not made by this run)\n", r.c_str());
    return 0;
}

}  // namespace brume::app
