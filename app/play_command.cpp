#include "app/play_command.h"

#include "app/cli_util.h"
#include "app/progress.h"
#include "app/video.h"
#include "render/atomic_file.h"
#include "render/image_io.h"
#include "render/methods/registry.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

// Set by SIGINT/SIGTERM: the frame being rendered is finished and written, then playback stops.
// A signal handler can only reach process-wide state, hence this one global.
std::atomic<bool> g_stop_requested{false};
extern "C" void request_stop(int) { g_stop_requested.store(true); }

struct FrameRange {
    int first = 0;
    int last = 0;  // inclusive
};

FrameRange parse_frames(const std::string& text, int frame_count) {
    long long first = 0, last = frame_count - 1;
    if (!text.empty()) {
        // A dash after the first character separates A and B ("-3" alone is a negative N).
        const std::size_t dash = text.find('-', 1);
        const std::optional<long long> a = parse_whole_number(std::string_view(text).substr(0, dash));
        const std::optional<long long> b =
            dash == std::string::npos ? a : parse_whole_number(std::string_view(text).substr(dash + 1));
        if (!a || !b) throw std::invalid_argument("--frames '" + text + "' is not A-B or N (0-based, inclusive)");
        first = *a;
        last = *b;
    }
    if (last < first)
        throw std::invalid_argument("--frames " + text + " is a reversed range: write A-B with A <= B");
    if (first < 0 || first >= frame_count)
        throw std::invalid_argument("--frames " + text + " is outside the preset's frames 0-" +
                                    std::to_string(frame_count - 1));
    if (last >= frame_count) {
        // Farm schedulers cut sequences into equal chunks; the last one may run past the end.
        std::printf("--frames %s: the preset ends at frame %d; rendering %lld-%d\n", text.c_str(), frame_count - 1,
                    first, frame_count - 1);
        last = frame_count - 1;
    }
    return {int(first), int(last)};
}

std::string frame_path(const fs::path& dir, const std::string& name, int frame, const char* ext) {
    char file[64];
    std::snprintf(file, sizeof file, ".%04d.%s", frame, ext);
    return (dir / (name + file)).string();
}

}  // namespace

void add_play_command(CLI::App& app, PlayArgs& args) {
    CLI::App* cmd = app.add_subcommand("play", "Simulate a preset and render its frames (and a video)");
    cmd->add_option("preset", args.preset, "Preset file or built-in name (see --list); none plays the default");
    cmd->add_option("-o,--output", args.output_dir, "Directory for NAME.####.png / .exr (created if missing)");
    cmd->add_option("--frames", args.frames, "Frames A-B (0-based, inclusive) or N; default all");
    cmd->add_option("--format", args.formats, "Comma-separated: png, exr (default png)");
    cmd->add_option("--video", args.video, "Also encode the frames with ffmpeg, e.g. out/plume.mp4");
    cmd->add_option("--size", args.size, "Override the preset's resolution, WxH");
    cmd->add_option("--method", args.method,
                    "NAME[:SETTING] (default: the preset's): ppll, reference or a comparison method (brume methods)");
    cmd->add_option("--exposure", args.exposure, "PNG exposure in stops (default: the preset's)")
        ->each([&args](const std::string&) { args.exposure_set = true; });
    cmd->add_flag("--list", args.list, "List the built-in presets and exit");
    cmd->add_option("--device", args.device, "Vulkan device (substring of its name; default lavapipe)");
    cmd->add_flag("--validate", args.validate, "Enable the Vulkan validation layers; any message fails the run");
    cmd->add_option("--max-memory", args.max_memory, "Node-pool budget, e.g. 256M");
}

int run_play(const PlayArgs& args) {
    if (args.list) {
        const std::string def = default_preset_name();
        for (const std::string& name : builtin_preset_names()) {
            const auto p = builtin_preset(name);
            std::printf("%-12s %s%s\n", name.c_str(), p ? p->description.c_str() : "",
                        name == def ? " (default)" : "");
        }
        return 0;
    }
    Preset preset = resolve_preset(args.preset.empty() ? default_preset_name() : args.preset);
    if (!args.size.empty()) parse_size(args.size, preset.scene.camera.width, preset.scene.camera.height);
    for (const VolumeReport& v : prepare_preset(preset)) print_volume_report(v);
    const std::string method = args.method.empty() ? preset.render.method : args.method;
    const double exposure = args.exposure_set ? args.exposure : preset.render.exposure;
    if (!std::isfinite(exposure)) throw std::invalid_argument("--exposure must be a finite number of stops");
    const FrameRange range = parse_frames(args.frames, preset.timeline.frame_count());

    bool png = false, exr = false;
    for (std::size_t start = 0; start <= args.formats.size();) {
        const std::size_t comma = args.formats.find(',', start);
        const std::string f = args.formats.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (f == "png") png = true;
        else if (f == "exr") exr = true;
        else throw std::invalid_argument("--format '" + f + "' is not png or exr");
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (!args.video.empty() && !png) throw std::invalid_argument("--video encodes the PNG frames: add png to --format");

    // Everything that can be refused is refused before the first frame.
    const fs::path dir = args.output_dir.empty() ? fs::path(preset.name) : fs::path(args.output_dir);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) throw std::runtime_error("cannot create output directory " + dir.string() + (ec ? ": " + ec.message() : ""));
    check_writable_path(dir / "probe");
    if (!args.video.empty()) {
        check_writable_path(args.video);
        if (ffmpeg_version().empty())
            throw std::runtime_error("--video needs the ffmpeg command, which is not installed "
                                     "(Debian: apt-get install ffmpeg, or run .ci/install-deps)");
    }

    // Options reach every method that honours them (the registry says which).
    MethodOptions options;
    unsigned given = 0;
    if (!args.max_memory.empty()) {
        options.max_pool_bytes = parse_bytes(args.max_memory);
        given |= kHonoursMaxMemory;
    }
    check_method_options(method, given);
    std::unique_ptr<vk::Device> device;
    if (find_method(method).needs_device) {
        vk::DeviceOptions device_options;
        device_options.device_name = args.device;
        device_options.validate = args.validate;
        device = std::make_unique<vk::Device>(device_options);
    }
    std::unique_ptr<Method> renderer = make_method(device.get(), method, options);

    g_stop_requested = false;
    auto previous_int = std::signal(SIGINT, request_stop);
    auto previous_term = std::signal(SIGTERM, request_stop);

    // Frames before the range are simulated, not rendered: the simulation is deterministic, so
    // frames A-B of a split job are exactly those of a full run (replay; see README "Farms").
    const auto sim_start = std::chrono::steady_clock::now();
    Simulator sim(preset);
    sim.advance_to_frame(range.first);
    const double replay_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sim_start).count();
    double sim_s = 0.0;

    std::printf("%s: frames %d-%d of %d at %dx%d, %.4g fps, method %s%s -> %s\n", preset.name.c_str(), range.first,
                range.last, preset.timeline.frame_count(), preset.scene.camera.width, preset.scene.camera.height,
                preset.timeline.fps, method.c_str(), device ? (" on " + device->name()).c_str() : "", dir.string().c_str());
    if (range.first > 0) std::printf("replayed the simulation to frame %d in %.2f s\n", range.first, replay_s);

    Progress progress(preset.name, range.last - range.first + 1);
    Scene scene = preset.scene;
    const std::size_t static_spheres = preset.scene.spheres.size();
    int written = 0;
    for (int frame = range.first; frame <= range.last; ++frame) {
        if (frame > range.first) {
            const auto t0 = std::chrono::steady_clock::now();
            sim.step_frame();
            sim_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        scene.spheres.resize(static_spheres);
        sim.append_spheres(scene.spheres);
        scene.camera = camera_at(preset, sim.time());
        scene.camera.width = preset.scene.camera.width;
        scene.camera.height = preset.scene.camera.height;
        const Image image = renderer->render(scene, nullptr);
        refuse_non_finite(image, "frame " + std::to_string(frame));
        if (exr) write_exr(image, frame_path(dir, preset.name, frame, "exr"));
        if (png) write_png(image, frame_path(dir, preset.name, frame, "png"), exposure);
        ++written;
        progress.frame_done(frame, std::to_string(scene.spheres.size()) + (scene.spheres.size() == 1 ? " sphere" : " spheres"));
        if (g_stop_requested) break;
    }
    progress.finish();
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);

    if (device && device->validation_message_count() > 0) {
        for (const std::string& m : device->take_validation_messages()) std::fprintf(stderr, "%s\n", m.c_str());
        std::fprintf(stderr, "brume: error: the Vulkan validation layer reported problems (above)\n");
        return 3;
    }
    std::printf("wrote %d frame%s in %.1f s (simulation %.2f s) to %s\n", written, written == 1 ? "" : "s",
                progress.elapsed_seconds(), sim_s, dir.string().c_str());
    if (g_stop_requested) {
        std::fprintf(stderr, "brume: interrupted after %d frames; every written frame is complete\n", written);
        return 130;
    }
    if (!args.video.empty()) {
        encode_video((dir / (preset.name + ".%04d.png")).string(), range.first, written, preset.timeline.fps, args.video,
                     dir / (preset.name + ".ffmpeg.log"));
        std::printf("wrote %s\n", args.video.c_str());
    }
    return 0;
}

}  // namespace brume::app
