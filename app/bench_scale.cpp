#include "app/bench_scale.h"

#include "app/charts.h"
#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/output_paths.h"
#include "render/atomic_file.h"
#include "render/fast_tracer.h"
#include "render/frame/list_heat_map.h"
#include "render/image_compare.h"
#include "render/methods/ppll.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "render/vk/resources.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/scene_file.h"
#include "sim/simulator.h"
#include "sim/smoke_cloud_scene.h"
#include "sim/vdb/volume_loader.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

// Every exact method of the catalogue, then `sorted`: the fast inexact method users have today.
std::vector<std::string> default_scale_methods() {
    std::vector<std::string> specs;
    for (const MethodEntry& entry : method_catalogue())
        if (entry.exact) specs.push_back(entry.name);
    specs.push_back("sorted");
    return specs;
}

// A shipped preset's frame a third of the way in (emitters have filled the view), at w x h.
Scene preset_frame(const std::string& name, int w, int h) {
    std::optional<Preset> preset = builtin_preset(name);
    prepare_preset(*preset);
    Simulator sim(*preset);
    sim.advance_to_frame(preset->timeline.frame_count() / 3);
    Scene scene = preset->scene;
    sim.append_spheres(scene.spheres);
    scene.camera = camera_at(*preset, sim.time());
    scene.camera.width = w;
    scene.camera.height = h;
    return scene;
}

// Median frame time of `method` on `scene` (GPU time for GPU methods, wall time otherwise), after
// a warm-up of at least one frame and `warm_ms` (cli_util.h); the last frame's image and passes.
double time_method(Method& method, const Scene& scene, int frames, double warm_ms, Image& image, std::string& passes) {
    warm_up([&] { image = method.render(scene); }, warm_ms);
    std::vector<double> times, walls;
    for (int f = 0; f < frames; ++f) {
        FrameStats stats;
        const auto t0 = std::chrono::steady_clock::now();
        image = method.render(scene, &stats);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        times.push_back(method.gpu() ? stats.total_ms : wall);
        walls.push_back(wall);
        if (f + 1 == frames) {
            std::ostringstream text;
            for (const PassTime& p : stats.passes) text << " " << p.name << "=" << int(p.ms + 0.5);
            // On a real GPU the device time leaves out what the host spends around it (recording,
            // upload, read-back): the wall clock says what a user waits for a frame.
            if (method.gpu()) text << " wall=" << std::fixed << std::setprecision(1) << median(walls);
            if (stats.memory_bytes > 0) text << " memory=" << vk::format_bytes(stats.memory_bytes);
            if (stats.long_list_pixels > 0) text << " [" << stats.long_list_pixels << " px by the general path]";
            passes = text.str();
        }
    }
    return median(times);
}

// A scene's list figures from the list-length pass (render/frame/list_heat_map.h): ppll's append test
// without its resolve, so they hold at any list length on any device (lavapipe's loop limit makes ppll
// refuse the 1,000,000-sphere cloud's frame, and the row is still worth measuring by the other methods).
ListLengthFigures list_figures(vk::Device& device, const Scene& scene) {
    ListHeatMap counter(device);
    return list_length_figures(counter.render(scene, nullptr));
}

struct Row {
    std::size_t spheres = 0;
    std::string method;
    double ms = 0.0;
};

}  // namespace

int run_bench_scale(const BenchArgs& args) {
    int w = 640, h = 360;
    if (!args.size.empty()) parse_size(args.size, w, h);
    std::vector<std::size_t> counts;
    for (int n : parse_int_list(args.spheres)) {
        if (n < 1 || std::size_t(n) > kMaxSpheres)
            throw UsageError("--spheres: counts must be from 1 to " + std::to_string(kMaxSpheres) +
                                        ", as in a scene file (got " + std::to_string(n) + ")");
        counts.push_back(std::size_t(n));
    }
    const std::vector<std::string> specs = args.methods.empty() ? default_scale_methods() : split_method_list(args.methods);
    if (specs.empty()) throw UsageError("--methods: no method named (brume methods lists them)");
    for (const std::string& spec : specs) check_method_usage(spec, 0);  // a bad spec is refused before any work
    if (!args.output_dir.empty()) check_folder_can_be_made(args.output_dir);  // made when the figures are in

    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    vk::Device device(device_options);
    const double warm_ms = warm_up_ms(device.properties().deviceType);
    const char* threads = std::getenv("LP_NUM_THREADS");
    std::printf("# brume bench scale: smoke clouds at %dx%d (radius ~ N^-1/3, fixed seed), device %s "
                "(LP_NUM_THREADS=%s), median of %d frames after a warm-up of 1 frame and %.0f ms\n",
                w, h, device.name().c_str(), threads ? threads : "default", args.frames, warm_ms);
    std::printf("# host: %s\n", host_cpu_description().c_str());
    std::printf("# fragments (ppll's list nodes), mean and longest list from the list-length pass; ns/frag = ms per "
                "fragment; vs_ref = reference ms / method ms (above 1: faster than the CPU reference); a method that "
                "refuses a frame says why in its row; trace runs %s code\n",
                fast_trace_instructions());
    std::printf("%9s %11s %7s %6s  %-12s %10s %9s %8s %9s %s\n", "spheres", "fragments", "mean", "max", "method",
                "ms", "ns/frag", "vs_ref", "max_err", "passes (ms, last frame)");

    std::vector<Row> rows;
    std::map<std::size_t, std::uint64_t> fragments_of;
    for (std::size_t n : counts) {
        const Scene scene = make_smoke_cloud_scene(n, w, h);
        const ListLengthFigures lists = list_figures(device, scene);
        fragments_of[n] = lists.total;

        std::map<std::string, double> ms_of;
        std::map<std::string, std::string> passes_of;
        std::map<std::string, std::string> refused_of;
        Image reference_image;
        std::vector<std::pair<std::string, Image>> images;
        for (const std::string& spec : specs) {
            std::unique_ptr<Method> method = make_method(&device, spec);
            Image image;
            try {
                ms_of[spec] = time_method(*method, scene, args.frames, warm_ms, image, passes_of[spec]);
            } catch (const ListResolveError& e) {
                // ppll refusing a frame it cannot resolve on this device: a finding of the bench, not
                // a failure of it (anything else still ends the run).
                refused_of[spec] = e.what();
                continue;
            }
            if (spec == "reference") reference_image = image;
            images.emplace_back(spec, std::move(image));
        }
        if (reference_image.width == 0) reference_image = make_method(nullptr, "reference")->render(scene);
        const double ref_ms = ms_of.count("reference") ? ms_of["reference"] : 0.0;
        for (const auto& [spec, message] : refused_of)
            std::printf("%9zu %11llu %7.1f %6.0f  %-12s refused: %s\n", n, (unsigned long long)lists.total, lists.mean,
                        lists.longest, spec.c_str(), message.c_str());
        for (const auto& [spec, image] : images) {
            const ImageDiff diff = compare_images(image, reference_image, 0.0);
            const double max_err = diff.peak > 0 ? diff.max_abs / diff.peak : diff.max_abs;
            const double ms = ms_of[spec];
            char ratio[32] = "-";
            if (ref_ms > 0) std::snprintf(ratio, sizeof ratio, "%.2fx", ref_ms / ms);
            std::printf("%9zu %11llu %7.1f %6.0f  %-12s %10.1f %9.1f %8s %9.1e %s\n", n, (unsigned long long)lists.total,
                        lists.mean, lists.longest, spec.c_str(), ms,
                        ms * 1e6 / double(std::max<std::uint64_t>(lists.total, 1)), ratio, max_err, passes_of[spec].c_str());
            rows.push_back({n, spec, ms});
        }
        std::fflush(stdout);
    }

    if (!args.output_dir.empty()) {
        const fs::path dir(args.output_dir);
        make_folder(dir);
        std::ostringstream data;
        data << "# method fragments ms\n";
        std::ostringstream plot;
        plot << "set terminal svg size 720,440\nset output 'scale.svg'\nset logscale xy\nset key left top\n"
             << "set xlabel 'fragments (list nodes) per frame'\nset ylabel 'ms per frame'\n"
             << "set title 'brume bench scale: " << w << "x" << h << " smoke clouds, " << device.name() << "'\nplot ";
        for (std::size_t m = 0; m < specs.size(); ++m) {
            data << "\n\n# " << specs[m] << "\n";
            for (const Row& row : rows)
                if (row.method == specs[m]) data << specs[m] << " " << fragments_of[row.spheres] << " " << row.ms << "\n";
            plot << (m ? ", " : "") << "'scale.dat' index " << m << " using 2:3 with linespoints title '" << specs[m] << "'";
        }
        plot << "\nset terminal pngcairo size 720,440\nset output 'scale.png'\nreplot\n";
        write_file_atomically(dir / "scale.dat", data.str());
        for (const std::string& file : draw_charts(dir, {{"scale", plot.str()}})) std::printf("# chart: %s\n", file.c_str());
    }
    // The shipped presets, a third of the way in, with every method of the run: frame time and FPS.
    if (!args.no_presets) {
        std::printf("\n# shipped presets at %dx%d, frame at a third of the timeline: ms (fps) per method\n", w, h);
        std::printf("%-12s %9s %9s", "preset", "spheres", "fragments");
        for (const std::string& spec : specs) std::printf(" %16s", spec.c_str());
        std::printf("\n");
        std::string auto_paths;  // which path auto took on each preset, said under the table
        for (const std::string& name : builtin_preset_names()) {
            const Scene scene = preset_frame(name, w, h);
            // The reference column is the exact model's frame on every preset, crossing and pop too,
            // whose own technique (per-sphere) would give the reference's per-sphere mode: the competitor
            // is the same computation on every row.
            Scene exact_scene = scene;
            exact_scene.render.shadow_technique = ShadowTechnique::Accurate;
            std::printf("%-12s %9zu %9llu", name.c_str(), scene.spheres.size(),
                        (unsigned long long)list_figures(device, scene).total);
            for (const std::string& spec : specs) {
                // The exact shadows of the CPU reference take seconds a frame at this size (vdb-cloud
                // 37 s at 640x360 on the project's 2-core machine): one frame, not warmed up, marked
                // '*', rather than stalling the table for minutes.
                const bool one_frame = spec == "reference" && scene.lighting.shadows;
                std::unique_ptr<Method> method = make_method(&device, spec);
                Image image;
                std::string passes;
                double ms = 0.0;
                try {
                    if (one_frame) {
                        const auto t0 = std::chrono::steady_clock::now();
                        image = method->render(exact_scene);
                        ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                    } else {
                        ms = time_method(*method, scene, args.frames, warm_ms, image, passes);
                    }
                } catch (const ListResolveError&) {
                    // As in the clouds' table: the device's loop budget refused this frame (tiles on
                    // vdb-cloud, lavapipe), which is a finding; the cell says so and the table goes on.
                    std::printf(" %16s", "refused");
                    continue;
                }
                const std::string decided = " decide (cpu): ";
                if (const std::size_t at = passes.find(decided); at != std::string::npos)
                    auto_paths += (auto_paths.empty() ? "" : ", ") + name + " " +
                                  passes.substr(at + decided.size(), passes.find('=', at) - at - decided.size());
                char cell[48];
                if (one_frame) std::snprintf(cell, sizeof cell, "%.0f (%.2f)*", ms, 1000.0 / ms);
                else std::snprintf(cell, sizeof cell, "%.1f (%.1f)", ms, 1000.0 / ms);
                std::printf(" %16s", cell);
            }
            std::printf("\n");
            std::fflush(stdout);
        }
        if (!auto_paths.empty()) std::printf("# auto's path: %s\n", auto_paths.c_str());
        if (std::find(specs.begin(), specs.end(), "reference") != specs.end())
            std::printf("# *: the reference's exact shadows, one frame (not the median of %d)\n", args.frames);
    }

    return report_validation_messages(device) ? 3 : 0;
}

}  // namespace brume::app
