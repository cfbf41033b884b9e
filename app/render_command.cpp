#include "app/render_command.h"

#include "app/cli_util.h"
#include "app/frame_progress.h"
#include "app/output_paths.h"
#include "app/standard_streams.h"
#include "render/atomic_file.h"
#include "render/image_io.h"
#include "render/output_set.h"
#include "render/methods/reference_method.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/builtin_scenes.h"
#include "sim/camera_path.h"
#include "sim/preset_file.h"
#include "sim/scene_file.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

namespace brume::app {

void add_render_command(CLI::App& app, RenderArgs& args) {
    CLI::App* cmd = app.add_subcommand("render", "Render one scene to linear EXR and/or PNG");
    cmd->add_option("scene", args.scene,
                    "Scene file (TOML; - reads it from standard input); none renders the built-in default scene. A preset (a built-in's "
                    "name, or a file with a preset's sections) renders one still of it: frame 0, or --frame")
        ->check(refuse_empty_path);
    cmd->add_option("--frame", args.frame, "With a preset: the frame to render (0-based, as in play --frames; default 0)")
        ->check(refuse_non_frame_number);
    cmd->add_option("-o,--output", args.exr, "Linear float RGB OpenEXR output (- for standard output)")->check(refuse_empty_path);
    cmd->add_option("--png", args.png, "PNG output for people (exposure, then sRGB; - for standard output)")->check(refuse_empty_path);
    cmd->add_option("--method", args.method,
                    "NAME[:SETTING]: auto (the default, or a preset's [render_settings] method: the fastest exact path on this device), ppll (GPU, exact), "
                    "trace (CPU, exact), reference (CPU, double precision) or a comparison method (brume methods "
                    "lists them)");
    cmd->add_option("--stats", args.stats, "Write frame statistics as JSON (- for standard output)")->check(refuse_empty_path);
    cmd->add_option("--repeat", args.repeat, "Render N frames; statistics report medians")->check(CLI::Range(1, 100000));
    cmd->add_option("--size", args.size, "Override the scene's resolution, WxH");
    cmd->add_option("--exposure", args.exposure, "PNG exposure in stops (default 0, or a preset's)")
        ->each([&args](const std::string&) { args.exposure_set = true; });
    cmd->add_option("--device", args.device, "Vulkan device (a substring of its name, or #N as brume devices numbers them; default lavapipe)");
    cmd->add_flag("--validate", args.validate, "Enable the Vulkan validation layers; any message fails the run");
    cmd->add_option("--max-memory", args.max_memory, "Node-pool budget, e.g. 256M (default: half the device heap)");
    cmd->add_option("--pool-nodes", args.pool_nodes, "Initial node-pool size (default: estimated from the scene)")
        ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 40));
    cmd->add_option("--shadows", args.shadows,
                    "Shadow technique of the exact methods when the scene has shadows: accurate (default; for reference, "
                    "the exact model) or per-sphere (T_sun once per sphere; reference has that mode too); off renders "
                    "the scene without shadows. The comparison methods always shade per sphere")
        ->check(CLI::IsMember({"accurate", "per-sphere", "off"}));
    cmd->add_option("--threads", args.threads,
                    "CPU threads: the CPU tracers' (reference, trace, auto), and at most that many for any "
                    "method's host work (the accurate shadows' depth map, tiles' binning, a volume's import); 0 "
                    "or unset: every CPU this process may use: its affinity and CPU quota")
        ->check(CLI::Range(0, 1024));
}

namespace {

namespace fs = std::filesystem;

// Whether `render` was given a preset by name, or a file to read as one: when --frame says so, or
// when the name is a built-in preset's and nothing but a folder has that name (`brume play plume`
// writes ./plume/, and `brume render plume` is still a still of plume's frame 0). Any other file is
// read as a scene or a preset by its sections (load_scene_or_preset_file).
bool names_a_preset(const RenderArgs& args) {
    if (args.scene.empty()) return false;
    if (args.frame >= 0) return true;
    std::error_code ec;
    const fs::file_status status = fs::status(args.scene, ec);
    if (fs::is_directory(status)) return builtin_preset_toml(args.scene).has_value();
    if (fs::exists(status)) return false;
    // A missing name without a folder or an extension reads as a preset's: taken as one, a typo
    // (`render plumee`) is answered with the presets and the closest of them, not "cannot open".
    const fs::path path(args.scene);
    return builtin_preset(args.scene).has_value() || (!path.has_parent_path() && !path.has_extension());
}

// What the simulation of a preset still did, for the summary and the statistics.
struct StillReport {
    bool preset = false;
    std::uint32_t max_particles = 0;
    std::uint64_t skipped = 0;  // births the full max_particles budget skipped
};

// The scene of one frame of a preset: simulated up to the frame, with the camera of its path there.
Scene preset_still(const RenderArgs& args, Preset preset, double& exposure, StillReport& report) {
    if (!args.size.empty()) parse_size(args.size, preset.scene.camera.width, preset.scene.camera.height);
    const int frame = std::max(args.frame, 0);
    const int count = preset.timeline.frame_count();
    if (frame >= count)
        throw UsageError("--frame " + std::to_string(frame) + " is outside the preset's frames 0-" +
                                    std::to_string(count - 1));
    for (const VolumeReport& v : prepare_preset(preset)) print_volume_report(v);
    Simulator sim(preset);
    sim.advance_to_frame(frame);
    Scene scene = preset.scene;
    sim.append_spheres(scene.spheres);
    try {
        scene.camera = camera_at(preset, sim.time());
    } catch (const CameraPathError& e) {
        throw std::runtime_error("frame " + std::to_string(frame) + ": " + e.what());
    }
    scene.camera.width = preset.scene.camera.width;
    scene.camera.height = preset.scene.camera.height;
    scene.source = preset.name + " frame " + std::to_string(frame);
    if (!args.exposure_set) exposure = preset.render.exposure;
    report = {true, preset.timeline.max_particles, sim.skipped()};
    if (report.skipped > 0)  // a silent cap looks like a weak emitter (issue 14 item 4)
        std::printf("note: the particle budget max_particles = %u skipped %llu births up to frame %d\n",
                    report.max_particles, static_cast<unsigned long long>(report.skipped), frame);
    return scene;
}

// The path auto took for the last frame (its "decide (cpu): NAME" pass), or "" for any other method.
std::string path_taken(const FrameStats& last) {
    constexpr std::string_view kDecided = "decide (cpu): ";
    for (const PassTime& p : last.passes)
        if (p.name.starts_with(kDecided)) return p.name.substr(kDecided.size());
    return "";
}

struct Timing {
    std::vector<std::vector<double>> pass_ms;  // per pass, per frame
    std::vector<std::string> pass_names;
    std::vector<double> total_ms;
};

std::string stats_json(const RenderArgs& args, const Scene& scene, const std::string& device, const Timing& timing,
                       const FrameStats& last, bool on_gpu, const StillReport& still) {
    std::ostringstream j;
    j.precision(10);
    j << "{\n";
    j << "  \"scene\": " << json_string(scene.source) << ",\n";
    j << "  \"method\": " << json_string(args.method) << ",\n";
    if (const std::string taken = path_taken(last); !taken.empty()) j << "  \"taken\": " << json_string(taken) << ",\n";
    j << "  \"device\": " << json_string(device) << ",\n";
    j << "  \"width\": " << scene.camera.width << ",\n  \"height\": " << scene.camera.height << ",\n";
    j << "  \"spheres\": " << scene.spheres.size() << ",\n  \"boxes\": " << scene.boxes.size() << ",\n";
    j << "  \"frames\": " << timing.total_ms.size() << ",\n";
    if (still.preset) j << "  \"skipped_births\": " << still.skipped << ",\n";
    // The light model's shadows as this method computed them (docs/accuracy.md).
    // The exact methods (ppll, tiles, trace, auto) sample T_sun along their segments; the methods that
    // composite whole spheres use the per-sphere term whatever the scene asks.
    const bool integrates = find_method(args.method).exact;
    const bool per_sphere = scene.render.shadow_technique == ShadowTechnique::PerSphere;
    const char* shadows = !scene.lighting.shadows ? "off"
                          : !on_gpu              ? (per_sphere ? "per-sphere" : "exact")  // the reference's modes
                          : integrates           ? kShadowTechniqueNames[int(scene.render.shadow_technique)]
                                                 : "per-sphere";
    j << "  \"shadows\": " << json_string(shadows) << ",\n";
    const char* clock = on_gpu ? "gpu_ms" : "cpu_ms";
    j << "  \"" << clock << "\": {";
    for (std::size_t p = 0; p < timing.pass_names.size(); ++p)
        j << json_string(timing.pass_names[p]) << ": " << median(timing.pass_ms[p]) << ", ";
    j << "\"total\": " << median(timing.total_ms) << "}";
    if (on_gpu) j << ",\n  \"memory_bytes\": " << last.memory_bytes;
    if (last.list_stats) {  // the list figures exist for methods that keep per-pixel lists
        j << ",\n  \"fragments\": " << last.fragments;
        j << ",\n  \"pool_capacity\": " << last.pool_capacity;
        j << ",\n  \"pool_bytes\": " << last.pool_bytes;
        j << ",\n  \"regrows\": " << last.regrows;
        j << ",\n  \"max_list_length\": " << last.max_list_length;
        j << ",\n  \"mean_list_length\": " << last.mean_list_length;
        j << ",\n  \"nonempty_pixels\": " << last.nonempty_pixels;
        j << ",\n  \"long_list_pixels\": " << last.long_list_pixels;
    }
    j << "\n}\n";
    return j.str();
}

}  // namespace

int run_render(const RenderArgs& command_line) {
    RenderArgs args = command_line;
    // --threads holds every parallel loop of the run to that many CPUs, a GPU method's host work and a
    // volume's import too, and lavapipe's threads.
    hold_run_to_threads(args.threads);
    args.scene = input_path(args.scene);  // "-": the scene on standard input
    std::string exr = args.exr, png = args.png;
    // The default images only when no output is named: `--stats -` alone writes no brume.exr.
    if (exr.empty() && png.empty() && args.stats.empty()) {
        exr = "brume.exr";
        png = "brume.png";
    }
    // Refuse before any work rather than fail after writing some outputs and not others.
    if (!exr.empty()) check_output_format("-o", exr, ".exr");
    if (!png.empty()) check_output_format("--png", png, ".png");
    for (const std::string& out : {exr, png, args.stats})
        if (!out.empty()) check_writable_path(out);
    const std::vector<NamedPath> output_names = {{"-o", exr}, {"--png", png}, {"--stats", args.stats}};
    check_outputs_distinct(output_names, {{"the scene", args.scene}});
    for (const NamedPath& out : output_names)
        if (names_standard_output(out.path)) claim_standard_output(out.option, out.option != "--stats");

    double exposure = args.exposure;
    if (args.scene.empty() && args.frame >= 0)
        throw UsageError("--frame picks a frame of a preset (brume play --list); the built-in default scene is a still");
    std::optional<Preset> preset;
    Scene scene;
    if (args.scene.empty())
        scene = default_scene();
    else if (names_a_preset(args)) {
        preset = resolve_preset(args.scene);
        refuse_still_scene(*preset, "--frame picks a frame of a preset");
    }
    else if (SceneOrPreset file = load_scene_or_preset_file(args.scene); file.preset)
        preset = std::move(file.preset);
    else
        scene = std::move(*file.scene);
    // A preset's own method unless --method names one, as play and preview do.
    if (args.method.empty()) args.method = preset ? preset->render.method : "auto";
    StillReport still;
    if (preset) scene = preset_still(args, std::move(*preset), exposure, still);
    else if (!args.size.empty()) parse_size(args.size, scene.camera.width, scene.camera.height);
    if (args.shadows == "off") scene.lighting.shadows = false;
    else if (!args.shadows.empty())
        scene.render.shadow_technique = args.shadows == "per-sphere" ? ShadowTechnique::PerSphere : ShadowTechnique::Accurate;
    if (!std::isfinite(exposure)) throw UsageError("--exposure must be a finite number of stops");
    std::vector<NamedPath> volumes;
    for (const VdbVolume& v : scene.volumes)
        if (v.source.file.rfind("builtin:", 0) != 0)
            volumes.push_back({"the volume", (fs::path(v.source.base_dir) / v.source.file).string()});
    check_outputs_distinct(output_names, volumes);
    for (const VolumeReport& v : convert_scene_volumes(scene)) print_volume_report(v);
    if (args.method.rfind("reference", 0) != 0) note_outsized_spheres(scene);

    // Options reach every method that honours them (the registry says which); one given to a
    // method that would ignore it is refused rather than silently dropped.
    unsigned given = 0;
    MethodOptions options;
    if (!args.max_memory.empty()) {
        options.max_pool_bytes = parse_bytes(args.max_memory);
        given |= kHonoursMaxMemory;
    }
    if (args.pool_nodes) {
        options.initial_pool_nodes = args.pool_nodes;
        given |= kHonoursPoolNodes;
    }
    options.threads = args.threads;  // every method runs within it (cap_usable_cpus, at the start)
    check_method_usage(args.method, given);
    check_device_options(args.method, args.device, args.validate);
    const bool on_gpu = find_method(args.method).needs_device;

    Timing timing;
    FrameStats last{};
    Image image;
    std::string device_name = "cpu";
    std::unique_ptr<vk::Device> device;
    if (on_gpu) {
        vk::DeviceOptions device_options;
        device_options.device_name = args.device;
        device_options.validate = args.validate;
        device = std::make_unique<vk::Device>(device_options);
        device_name = device->name();
    }
    std::unique_ptr<Method> method = make_method(device.get(), args.method, options);
    // The method as it runs, for the line and the statistics: "kbuf" and "kbuf:08" read "kbuf:8".
    args.method = method->name();
    // The exact reference's shadowed frames take seconds to minutes (vdb-cloud at 640x360: half a
    // minute on two cores): their progress on a terminal (stderr; nothing in a log).
    std::atomic<std::uint64_t> pixels_done{0};
    auto* reference = dynamic_cast<ReferenceMethod*>(method.get());
    if (reference) reference->count_pixels_into(&pixels_done);
    // Timed GPU frames follow one untimed frame: lavapipe compiles shaders and the first frame
    // touches fresh memory, which would otherwise dominate a short run's figures.
    // The pool grows on the first frame that needs it, usually the untimed one: its regrows count.
    int regrows = 0;
    if (on_gpu && (!args.stats.empty() || args.repeat > 1)) {
        method->render(scene, &last);
        regrows += last.regrows;
    }
    for (int f = 0; f < args.repeat; ++f) {
        {
            std::optional<FrameProgress> progress;
            if (reference)
                progress.emplace(args.repeat > 1 ? "reference, frame " + std::to_string(f + 1) + " of " +
                                                       std::to_string(args.repeat)
                                                 : std::string("reference"),
                                 std::uint64_t(scene.camera.width) * std::uint64_t(scene.camera.height), pixels_done);
            image = method->render(scene, &last);
        }
        regrows += last.regrows;
        if (timing.pass_names.empty()) {
            for (const PassTime& p : last.passes) timing.pass_names.push_back(p.name);
            timing.pass_ms.resize(last.passes.size());
        }
        for (std::size_t p = 0; p < last.passes.size() && p < timing.pass_ms.size(); ++p)
            timing.pass_ms[p].push_back(last.passes[p].ms);
        timing.total_ms.push_back(last.total_ms);
    }
    if (device && device->validation_message_count() > 0) {
        for (const std::string& m : device->take_validation_messages()) std::fprintf(stderr, "%s\n", m.c_str());
        std::fprintf(stderr, "brume: error: the Vulkan validation layer reported problems (above)\n");
        return 3;
    }

    refuse_non_finite(image, "the frame");
    last.regrows = regrows;  // over every frame this run rendered
    // All of the run's outputs or none: each is written in full before any replaces an old file.
    OutputSet outputs;
    if (!exr.empty()) outputs.stage(exr, exr_bytes(image, exr));
    if (!png.empty()) outputs.stage(png, png_bytes(image, png, exposure));
    if (!args.stats.empty()) outputs.stage(args.stats, stats_json(args, scene, device_name, timing, last, on_gpu, still));
    outputs.commit();

    const std::string taken = path_taken(last);
    const std::string method_shown = taken.empty() ? args.method : args.method + " (took " + taken + ")";
    std::printf("%s: %dx%d, %s, %s, method %s on %s: %.2f ms (median of %d)", scene.source.c_str(), scene.camera.width,
                scene.camera.height, count_of(scene.spheres.size(), "sphere", "spheres").c_str(),
                count_of(scene.boxes.size(), "box", "boxes").c_str(), method_shown.c_str(),
                device_name.c_str(), median(timing.total_ms), args.repeat);
    if (last.list_stats)
        std::printf(", %llu fragments, longest list %u", (unsigned long long)last.fragments, last.max_list_length);
    std::printf("\n");
    const std::pair<const std::string&, const char*> written[] = {{exr, "EXR"}, {png, "PNG"}, {args.stats, "statistics"}};
    for (const auto& [out, what] : written)
        if (names_standard_output(out)) std::printf("wrote the %s to standard output\n", what);
        else if (!out.empty()) std::printf("wrote %s\n", out.c_str());
    return 0;
}

}  // namespace brume::app
