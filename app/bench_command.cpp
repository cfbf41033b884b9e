#include "app/bench_command.h"
#include "app/bench_scale.h"

#include "app/bench_methods.h"
#include "app/bench_preview.h"
#include "app/bench_shadows.h"
#include "app/bench_vdb.h"
#include "app/cli_util.h"
#include "app/host_cpu.h"
#include "app/standard_streams.h"
#include "render/image_compare.h"
#include "render/methods/fill_ceiling.h"
#include "render/methods/ppll.h"
#include "render/fast_tracer.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/layers_scene.h"
#include "sim/simulator.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace brume::app {

namespace {

// The layers scene's spheres cover the whole frame, so each layer costs a full-screen pass and two list
// nodes a pixel: 1,024 layers already make about a billion list nodes at 800x600.
constexpr int kMaxBenchLayers = 1024;


// Barta & Kovács, "Order Independent Transparency with Per-Pixel Linked Lists", Tables 1-2 (ATI Radeon
// HD 5700, Direct3D 11): FPS against full-screen layers.
double paper_fps(int width, int layers) {
    static const double t800[] = {90, 49, 32, 23, 18, 14, 12, 10};
    static const double t1024[] = {51, 27, 18, 13, 10, 8, 6, 5};
    if (layers < 2 || layers > 16 || layers % 2) return 0.0;
    if (width == 800) return t800[layers / 2 - 1];
    if (width == 1024) return t1024[layers / 2 - 1];
    return 0.0;
}

// The time of the named pass of a frame (0 when the method has no such pass).
double pass_ms(const FrameStats& stats, const std::string& name) {
    for (const PassTime& p : stats.passes)
        if (p.name == name) return p.ms;
    return 0.0;
}

}  // namespace

void add_bench_command(CLI::App& app, BenchArgs& args) {
    CLI::App* cmd = app.add_subcommand("bench", "Benchmarks that print figures side by side");
    args.command = cmd;
    cmd->add_option("benchmark", args.which,
                    "methods (default: every method on every scene, charted), layers (Barta & Kovács, Tables 1-2), "
                    "scale (exact methods against list length), sim (simulation step), vdb (OpenVDB import: spheres against error), "
                    "preview (the preview window's frame, part by part; needs a display) or shadows (shadow techniques: speed "
                    "against accuracy)")
        ->check(CLI::IsMember({"methods", "layers", "scale", "sim", "vdb", "preview", "shadows"}));
    add_bench_methods_options(*cmd, args);
    cmd->add_option("--spheres", args.spheres, "bench scale: sphere counts of the smoke clouds, e.g. 1000,10000,100000")
        ->capture_default_str();
    cmd->add_flag("--no-presets", args.no_presets, "bench scale: skip the table of shipped presets");
    cmd->add_option("--particles", args.particles, "bench sim: live particles")->check(CLI::Range(std::size_t(1), std::size_t(10000000)));
    cmd->add_option("--steps", args.steps, "bench sim: steps timed (median reported)")->check(CLI::Range(1, 100000));
    cmd->add_option("--vdb-sample", args.vdb_sample, "bench vdb: built-in volumes, comma-separated (cloud, fog-sphere, sheet)")->capture_default_str();
    cmd->add_option("--vdb-sizes", args.vdb_sizes, "bench vdb: grid resolutions, e.g. 128,256")->capture_default_str();
    cmd->add_option("--tolerances", args.tolerances, "bench vdb: RMS optical-depth error tolerances")->capture_default_str();
    cmd->add_option("--preview-frames", args.preview_frames, "bench preview: frames each preset plays in the window")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    cmd->add_option("--presets", args.presets, "bench preview: presets, comma-separated (default: every shipped preset)");
    cmd->add_option("--shadow-scenes", args.shadow_scenes, "bench shadows: 'default' and shipped presets, comma-separated")
        ->capture_default_str();
    cmd->add_option("--shadow-frames", args.shadow_frames, "bench shadows: consecutive frames per preset")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--sizes", args.sizes, "bench layers: resolutions, e.g. 800x600,1024x768")->capture_default_str();
    cmd->add_option("--layers", args.layers, "bench layers: layer counts, e.g. 2-16:2 or 2,8,16 (even)")->capture_default_str();
    cmd->add_option("--frames", args.frames,
                    "timed frames per point, the median reported: bench layers, scale and shadows (default 9; shadows: "
                    "rounds); bench methods: frames of each static scene (default 5); bench preview: headless frames "
                    "per preset (default 9)")
        ->check(CLI::Range(1, 10000));
    cmd->add_option("--reference-frames", args.reference_frames, "bench layers: CPU reference frames per point (default 1)")
        ->check(CLI::Range(1, 100));
    cmd->add_flag("--no-reference", args.no_reference,
                  "bench layers and shadows: skip the CPU reference (bench shadows: its error columns too)");
    cmd->add_option("--device", args.device,
                    "Vulkan device (a substring of its name, or #N as brume devices numbers them; default lavapipe): bench methods, layers, scale, preview, shadows");
    cmd->add_flag("--validate", args.validate,
                  "Enable the Vulkan validation layers: bench methods, layers, scale, preview, shadows");
}

const std::vector<std::string>& bench_reads(const std::string& which) {
    // Which benchmark reads which option (run_bench and the bench_* files). A new option of a bench
    // joins its row here, or the bench refuses it.
    static const std::vector<std::pair<std::string, std::vector<std::string>>> kReads = {
        {"methods", {"--output", "--methods", "--scenes", "--size", "--frames", "--anim-frames", "--device", "--validate"}},
        {"layers", {"--sizes", "--layers", "--frames", "--reference-frames", "--no-reference", "--device", "--validate"}},
        {"scale", {"--spheres", "--methods", "--size", "--no-presets", "--frames", "--output", "--device", "--validate"}},
        {"sim", {"--particles", "--steps"}},
        {"vdb", {"--vdb-sample", "--vdb-sizes", "--tolerances", "--output"}},
        {"preview", {"--preview-frames", "--presets", "--size", "--frames", "--device", "--validate"}},
        {"shadows",
         {"--shadow-scenes", "--shadow-frames", "--methods", "--size", "--frames", "--no-reference", "--output", "--device",
          "--validate"}},
    };
    static const std::vector<std::string> kNone;
    for (const auto& [name, reads] : kReads)
        if (name == which) return reads;
    return kNone;
}

namespace {

bool reads_option(const std::string& which, const CLI::Option& opt) {
    for (const std::string& r : bench_reads(which))
        if (opt.check_name(r)) return true;
    return false;
}

}  // namespace

void restrict_bench_help(CLI::App& bench, const std::string& which) {
    if (bench_reads(which).empty()) return;
    for (CLI::Option* opt : bench.get_options()) {
        if (opt->get_positional() || opt->check_name("--help")) continue;
        if (!reads_option(which, *opt)) opt->group("");  // CLI11 leaves options of the empty group out of the help
    }
    bench.footer("(the options of bench " + which + "; brume bench --help lists those of every benchmark)");
}

void refuse_unread_bench_options(const BenchArgs& args) {
    if (!args.command) return;
    for (const CLI::Option* opt : args.command->get_options()) {
        if (opt->get_positional() || opt->count() == 0 || reads_option(args.which, *opt)) continue;
        std::string takes;
        for (const std::string& r : bench_reads(args.which)) takes += (takes.empty() ? "" : ", ") + r;
        // README ("Tour"): an option a command would ignore is refused, never silently dropped.
        throw UsageError(opt->get_name(false, true) + ": bench " + args.which + " does not use it; it takes " + takes +
                         " (see brume bench " + args.which + " --help)");
    }
}

bool bench_option_given(const BenchArgs& args, const std::string& name) {
    return args.command && args.command->count(name) > 0;
}

namespace {

int run_bench_sim(const BenchArgs& args) {
    const double ms = benchmark_step_ms(args.particles, args.steps);
    std::printf("# brume bench sim: one simulation step of a plume (gravity, buoyancy, wind, drag, 2-octave curl\n"
                "# noise, age curves, box collisions), one core, median of %d steps\n", args.steps);
    std::printf("# host: %s\n", host_cpu_description().c_str());
    std::printf("%10s %10s %14s\n", "particles", "ms/step", "ns/particle");
    std::printf("%10zu %10.3f %14.1f\n", args.particles, ms, ms * 1e6 / double(args.particles));
    return 0;
}

}  // namespace

int run_bench(const BenchArgs& args) {
    refuse_unread_bench_options(args);  // before any work or folder
    refuse_standard_output("-o", args.output_dir, "a benchmark's folder of results");
    if (args.which == "sim") return run_bench_sim(args);
    if (args.which == "methods") return run_bench_methods(args);
    if (args.which == "vdb") return run_bench_vdb(args);
    if (args.which == "scale") return run_bench_scale(args);
    if (args.which == "preview") return run_bench_preview(args);
    if (args.which == "shadows") return run_bench_shadows(args);
    std::vector<std::pair<int, int>> sizes;
    for (std::size_t start = 0; start <= args.sizes.size();) {
        const std::size_t comma = args.sizes.find(',', start);
        int w = 0, h = 0;
        parse_size(args.sizes.substr(start, comma == std::string::npos ? std::string::npos : comma - start), w, h);
        sizes.emplace_back(w, h);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    const std::vector<int> layer_counts = parse_int_list(args.layers);
    for (int n : layer_counts)
        if (n < 2 || n % 2 || n > kMaxBenchLayers)
            throw UsageError("--layers: counts must be even, from 2 to " + std::to_string(kMaxBenchLayers) +
                                        " (got " + std::to_string(n) + ")");

    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    vk::Device device(device_options);
    PpllMethod ppll(device);
    FillCeiling ceiling(device);
    const double warm_ms = warm_up_ms(device.properties().deviceType);
    const char* threads = std::getenv("LP_NUM_THREADS");
    std::printf("# brume bench layers: ppll on %s (LP_NUM_THREADS=%s), median of %d frames after a warm-up of 1 frame "
                "and %.0f ms;\n",
                device.name().c_str(), threads ? threads : "default", args.frames, warm_ms);
    std::printf("# host: %s\n", host_cpu_description().c_str());
    std::printf("# reference = CPU double-precision renderer, all cores, median of %d; paper = Barta & Kovács, Tables 1-2\n",
                args.reference_frames);
    std::printf("# fill_ms = the fill ceiling: the same impostors with a shader that does nothing but cannot be skipped "
                "(a never-taken discard); x_fill = total_ms / fill_ms\n");
    std::printf("# trace = the float CPU tracer (all cores, %s code, median of %d frames; what auto takes on a CPU "
                "device): trace_ms, its x_fill, ref/trace\n",
                fast_trace_instructions(), args.frames);
    std::printf("%-9s %6s %9s %9s %9s %9s %8s %8s %11s %9s %7s %10s %9s %9s %9s %7s %9s\n", "size", "layers", "opaque",
                "particle", "resolve", "total_ms", "fps", "paper", "Mlayers/s", "fill_ms", "x_fill", "ref_ms", "ref/ppll",
                "max_err", "trace_ms", "x_fill", "ref/trace");
    for (auto [w, h] : sizes) {
        for (int n : layer_counts) {
            const Scene scene = make_layers_scene(n, w, h);
            FrameStats stats;
            Image image;
            warm_up([&] { image = ppll.render(scene, &stats); }, warm_ms);  // and sizes the pool
            std::vector<double> opaque, particles, resolve, total;
            for (int f = 0; f < args.frames; ++f) {
                image = ppll.render(scene, &stats, false);
                opaque.push_back(pass_ms(stats, "clear+opaque") + pass_ms(stats, "sort (cpu)"));
                particles.push_back(pass_ms(stats, "particles"));
                resolve.push_back(pass_ms(stats, "resolve"));
                total.push_back(stats.total_ms);
            }
            const double ms = median(total);
            warm_up([&] { ceiling.render(scene); }, warm_ms);
            std::vector<double> fill;
            for (int f = 0; f < args.frames; ++f) {
                FrameStats fill_stats;
                ceiling.render(scene, &fill_stats);
                fill.push_back(pass_ms(fill_stats, "particles"));
            }
            const double fill_ms = median(fill);
            double ref_ms = 0.0, max_err = 0.0;
            if (!args.no_reference) {
                std::vector<double> ref_times;
                Image ref;
                for (int f = 0; f < args.reference_frames; ++f) {
                    const auto t0 = std::chrono::steady_clock::now();
                    ref = render_reference(scene);
                    ref_times.push_back(
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                }
                ref_ms = median(ref_times);
                const ImageDiff diff = compare_images(image, ref, 0.0);
                max_err = diff.peak > 0 ? diff.max_abs / diff.peak : diff.max_abs;
            }
            std::vector<double> trace_times;
            render_fast_trace(scene);  // warm-up
            for (int f = 0; f < args.frames; ++f) {
                const auto t0 = std::chrono::steady_clock::now();
                render_fast_trace(scene);
                trace_times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            }
            const double trace_ms = median(trace_times);
            const double paper = paper_fps(w, n);
            char size_text[32];
            std::snprintf(size_text, sizeof size_text, "%dx%d", w, h);
            char max_err_text[32] = "-";  // no reference, no error: "-", never a perfect-looking 0
            if (!args.no_reference) std::snprintf(max_err_text, sizeof max_err_text, "%.1e", max_err);
            std::printf("%-9s %6d %9.2f %9.2f %9.2f %9.2f %8.1f %8s %11.1f %9.2f %6.1fx %10s %9s %9s %9.2f %6.1fx %9s\n",
                        size_text, n,
                        median(opaque), median(particles), median(resolve), ms, 1000.0 / ms,
                        paper > 0 ? std::to_string(int(paper)).c_str() : "-", double(n) * w * h / (ms * 1e3), fill_ms,
                        ms / fill_ms,
                        args.no_reference ? "-" : std::to_string(int(ref_ms + 0.5)).c_str(),
                        args.no_reference ? "-" : (std::to_string(ref_ms / ms).substr(0, 5) + "x").c_str(), max_err_text,
                        trace_ms, trace_ms / fill_ms,
                        args.no_reference ? "-" : (std::to_string(ref_ms / trace_ms).substr(0, 5) + "x").c_str());
            std::fflush(stdout);
        }
    }
    return report_validation_messages(device) ? 3 : 0;
}

bool report_validation_messages(vk::Device& device) {
    if (device.validation_message_count() == 0) return false;
    for (const std::string& m : device.take_validation_messages()) std::fprintf(stderr, "%s\n", m.c_str());
    return true;
}

}  // namespace brume::app
