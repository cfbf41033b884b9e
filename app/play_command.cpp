#include "app/play_command.h"

#include "app/cli_util.h"
#include "app/frame_progress.h"
#include "app/output_paths.h"
#include "app/progress.h"
#include "app/standard_streams.h"
#include "app/stop_signals.h"
#include "app/video.h"
#include "render/atomic_file.h"
#include "render/image_io.h"
#include "render/methods/reference_method.h"
#include "render/methods/registry.h"
#include "render/output_set.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/camera_path.h"
#include "sim/simulator.h"
#include "sim/vdb/volume_loader.h"

#include <atomic>
#include <chrono>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

// Set by SIGINT, SIGTERM and SIGHUP (app/stop_signals.h): the frame being rendered is finished and
// written, then playback stops; a preroll or replay stops at its next step.
std::atomic<bool> g_stop_requested{false};

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
        if (!a || !b) throw UsageError("--frames '" + text + "' is not A-B or N (0-based, inclusive)");
        first = *a;
        last = *b;
    }
    if (last < first)
        throw UsageError("--frames " + text + " is a reversed range: write A-B with A <= B");
    if (first < 0 || first >= frame_count)
        throw UsageError("--frames " + text + " is outside the preset's frames 0-" +
                                    std::to_string(frame_count - 1));
    if (last >= frame_count) {
        // Farm schedulers cut sequences into equal chunks; the last one may run past the end.
        std::printf("--frames %s: the preset ends at frame %d; rendering %lld-%d\n", text.c_str(), frame_count - 1,
                    first, frame_count - 1);
        last = frame_count - 1;
    }
    return {int(first), int(last)};
}

// The containers ffmpeg writes H.264 into; a name that says otherwise (x.gif, a frame's .png) is
// refused before the first frame rather than after the last.
void check_video_name(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".mp4" || ext == ".mkv" || ext == ".mov" || ext == ".m4v") return;
    throw UsageError("--video " + path + ": the video is H.264, so its name must end in .mp4, .mkv, .mov or .m4v" +
                                (ext.empty() ? std::string() : " (not " + ext + ")"));
}

std::string frame_path(const fs::path& dir, const std::string& name, int frame, const char* ext) {
    char file[64];
    std::snprintf(file, sizeof file, ".%04d.%s", frame, ext);
    return (dir / (name + file)).string();
}

}  // namespace

void add_play_command(CLI::App& app, PlayArgs& args) {
    CLI::App* cmd = app.add_subcommand("play", "Simulate a preset and render its frames (and a video)");
    cmd->add_option("preset", args.preset, "Preset file (- reads it from standard input) or built-in name (see --list); none plays the default")
        ->check(refuse_empty_path);
    cmd->add_option("-o,--output", args.output_dir, "Directory for NAME.####.png / .exr (created if missing)")
        ->check(refuse_empty_path);
    cmd->add_option("--frames", args.frames, "Frames A-B (0-based, inclusive) or N; default all");
    cmd->add_option("--format", args.formats, "Comma-separated: png, exr (default png)");
    cmd->add_option("--video", args.video,
                    "Also encode the frames with ffmpeg (H.264: .mp4, .mkv, .mov or .m4v), e.g. out/plume.mp4; "
                    "ffmpeg's log is kept as DIR/NAME.ffmpeg.log only when encoding fails")
        ->check(refuse_empty_path);
    cmd->add_option("--size", args.size, "Override the preset's resolution, WxH");
    cmd->add_option("--method", args.method,
                    "NAME[:SETTING] (default: the preset's): auto, ppll, trace, reference or a comparison method (brume methods)");
    cmd->add_option("--exposure", args.exposure, "PNG exposure in stops (default: the preset's)")
        ->each([&args](const std::string&) { args.exposure_set = true; });
    cmd->add_flag("--list", args.list, "List the built-in presets and exit");
    cmd->add_option("--device", args.device, "Vulkan device (a substring of its name, or #N as brume devices numbers them; default lavapipe)");
    cmd->add_flag("--validate", args.validate, "Enable the Vulkan validation layers; any message fails the run");
    cmd->add_option("--max-memory", args.max_memory, "Node-pool budget, e.g. 256M");
    cmd->add_option("--threads", args.threads,
                    "CPU threads: the CPU tracers' (reference, trace, auto), and at most that many for any method's "
                    "host work (the accurate shadows' depth map, tiles' binning, a volume's import); 0 or unset: "
                    "every CPU this process may use, its affinity and CPU quota. With several jobs on one machine, "
                    "its CPUs divided among them")
        ->check(CLI::Range(0, 1024));
}

int run_play(const PlayArgs& args) {
    hold_run_to_threads(args.threads);  // every parallel loop of the run, and lavapipe's threads
    if (args.list) {
        const std::string def = default_preset_name();
        for (const std::string& name : builtin_preset_names()) {
            const auto p = builtin_preset(name);
            // Its frame count too: --frames and a farm's chunks are counted in it (README, "Farms").
            std::printf("%-12s %4d frames (%4.1f s at %2.0f fps)  %s%s\n", name.c_str(), p ? p->timeline.frame_count() : 0,
                        p ? p->timeline.frame_count() / p->timeline.fps : 0.0, p ? p->timeline.fps : 0.0,
                        p ? p->description.c_str() : "", name == def ? " (default)" : "");
        }
        return 0;
    }
    // "-": the preset on standard input (named by its [preset] name, else "stdin").
    Preset preset = resolve_preset(args.preset.empty() ? default_preset_name() : input_path(args.preset));
    refuse_still_scene(preset, "play plays a preset's frames");
    if (!args.size.empty()) parse_size(args.size, preset.scene.camera.width, preset.scene.camera.height);
    for (const VolumeReport& v : prepare_preset(preset)) print_volume_report(v);
    const std::string method = args.method.empty() ? preset.render.method : args.method;
    const double exposure = args.exposure_set ? args.exposure : preset.render.exposure;
    if (!std::isfinite(exposure)) throw UsageError("--exposure must be a finite number of stops");
    const FrameRange range = parse_frames(args.frames, preset.timeline.frame_count());

    bool png = false, exr = false;
    for (std::size_t start = 0; start <= args.formats.size();) {
        const std::size_t comma = args.formats.find(',', start);
        const std::string f = args.formats.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (f == "png") png = true;
        else if (f == "exr") exr = true;
        else throw UsageError("--format '" + f + "' is not png or exr");
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (!args.video.empty() && !png) throw UsageError("--video encodes the PNG frames: add png to --format");

    // Everything that can be refused is refused before the first frame, and nothing is created yet.
    refuse_standard_output("-o", args.output_dir, "play's folder of frames");
    const fs::path dir = args.output_dir.empty() ? fs::path(preset.name) : fs::path(args.output_dir);
    std::error_code ec;
    const fs::path base = existing_ancestor(dir);
    if (!fs::is_directory(base, ec))
        throw std::runtime_error("cannot create output directory " + dir.string() + ": " + base.string() + " is not a directory");
    check_writable_directory(base);
    // In a folder that exists already, each frame's own name too: one that is a directory (or a
    // socket) is refused now, not after the frames before it.
    if (base == dir)
        for (int frame = range.first; frame <= range.last; ++frame) {
            if (png) check_writable_path(frame_path(dir, preset.name, frame, "png"));
            if (exr) check_writable_path(frame_path(dir, preset.name, frame, "exr"));
        }
    if (!args.video.empty()) {
        check_video_name(args.video);
        // A video inside the frames folder is checked where that folder will be made.
        // The same folder however it is written: "out", "out/", "./out" or its absolute path.
        const auto folder = [](const fs::path& p) {
            fs::path n = fs::absolute(p.empty() ? fs::path(".") : p).lexically_normal();
            return n.has_filename() ? n : n.parent_path();
        };
        const fs::path video_dir = fs::path(args.video).parent_path();
        const bool in_frames_dir = folder(video_dir) == folder(dir) && !fs::exists(dir, ec);
        if (in_frames_dir)
            check_writable_directory(base);
        else
            check_writable_path(args.video);
        check_outputs_distinct({{"--video", args.video}}, {{"the preset", args.preset}});
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
    options.threads = args.threads;  // every method runs within it (cap_usable_cpus, at the start)
    check_method_usage(method, given);
    check_device_options(method, args.device, args.validate);
    std::unique_ptr<vk::Device> device;
    if (find_method(method).needs_device) {
        vk::DeviceOptions device_options;
        device_options.device_name = args.device;
        device_options.validate = args.validate;
        device = std::make_unique<vk::Device>(device_options);
    }
    std::unique_ptr<Method> renderer = make_method(device.get(), method, options);
    // The exact reference's shadowed frames take seconds to minutes each: within a frame, its share of
    // pixels replaces the run's bar on a terminal (app/frame_progress.h), which returns when it is done.
    std::atomic<std::uint64_t> pixels_done{0};
    auto* reference = dynamic_cast<ReferenceMethod*>(renderer.get());
    if (reference) reference->count_pixels_into(&pixels_done);

    const StopSignals stop_signals(g_stop_requested);

    // Frames before the range are simulated, not rendered: the simulation is deterministic, so
    // frames A-B of a split job are exactly those of a full run (replay; see README "Farms").
    // The preroll and the replay stop at the next step when a signal asks (issue 14 item 9).
    const auto sim_start = std::chrono::steady_clock::now();
    std::optional<Simulator> simulator;
    try {
        simulator.emplace(preset, &g_stop_requested);
        // Every frame's camera before the first frame is rendered: a path through an undefined view
        // is refused whole, not after the frames before it were written.
        for (int frame = range.first; frame <= range.last; ++frame) try {
                camera_at(preset, simulator->time_of_frame(frame));
            } catch (const CameraPathError& e) {
                throw std::runtime_error("frame " + std::to_string(frame) + ": " + e.what());
            }
        simulator->advance_to_frame(range.first);
        if (g_stop_requested) throw SimulationStopped("stopped");  // in the last step: no frame after it
    } catch (const SimulationStopped&) {
        std::fprintf(stderr, "brume: interrupted during the simulation (%.1f s in), before the first frame; nothing was written\n",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - sim_start).count());
        return 130;
    }
    Simulator& sim = *simulator;
    const double replay_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sim_start).count();
    double sim_s = replay_s;  // the summary's simulation time includes the preroll and the replay
    bool cap_noted = false;
    bool outsized_noted = method.rfind("reference", 0) == 0;  // note_outsized_spheres, once a run (none for the exact reference)

    std::printf("%s: frames %d-%d of %d at %dx%d, %.4g fps, method %s%s -> %s\n", preset.name.c_str(), range.first,
                range.last, preset.timeline.frame_count(), preset.scene.camera.width, preset.scene.camera.height,
                preset.timeline.fps, renderer->name().c_str(), device ? (" on " + device->name()).c_str() : "",
                dir.string().c_str());
    if (range.first > 0) std::printf("replayed the simulation to frame %d in %.2f s\n", range.first, replay_s);

    Progress progress(preset.name, range.last - range.first + 1);
    Scene scene = preset.scene;
    const std::size_t static_spheres = preset.scene.spheres.size();
    int written = 0;
    bool dir_made = false;
    // The folders made for the frames are removed again when no frame makes it into them.
    struct MadeFolders {
        std::vector<fs::path> deepest_first;
        bool keep = false;
        ~MadeFolders() {
            std::error_code ignored;
            if (!keep)
                for (const fs::path& d : deepest_first) fs::remove(d, ignored);  // only ever removes an empty folder
        }
    } made;
    for (int frame = range.first; frame <= range.last; ++frame) {
        if (frame > range.first) {
            const auto t0 = std::chrono::steady_clock::now();
            try {
                sim.step_frame();
            } catch (const SimulationStopped&) {
                break;  // every frame written so far is complete
            }
            sim_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        if (sim.skipped() > 0 && !cap_noted) {  // a silent cap looks like a weak emitter (issue 14 item 4)
            std::printf("note: the particle budget max_particles = %u is full at frame %d; births are skipped while it is\n",
                        preset.timeline.max_particles, frame);
            cap_noted = true;
        }
        scene.spheres.resize(static_spheres);
        sim.append_spheres(scene.spheres);
        scene.camera = camera_at(preset, sim.time());
        scene.camera.width = preset.scene.camera.width;
        scene.camera.height = preset.scene.camera.height;
        if (!outsized_noted) outsized_noted = note_outsized_spheres(scene);
        std::optional<FrameProgress> frame_progress;
        if (reference)
            frame_progress.emplace(preset.name + " frame " + std::to_string(frame),
                                   std::uint64_t(scene.camera.width) * std::uint64_t(scene.camera.height), pixels_done,
                                   stdout);  // the run's bar's stream, so that the two share its line
        const Image image = renderer->render(scene, nullptr);
        frame_progress.reset();
        refuse_non_finite(image, "frame " + std::to_string(frame));
        if (!dir_made) {
            for (fs::path p = dir; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path())
                made.deepest_first.push_back(p);
            fs::create_directories(dir, ec);
            if (ec || !fs::is_directory(dir))
                throw std::runtime_error("cannot create output directory " + dir.string() + (ec ? ": " + ec.message() : ""));
            dir_made = true;
        }
        // A frame's EXR and PNG are committed together: an interrupted or failed run never leaves one without the other.
        OutputSet outputs;
        if (exr) {
            const std::string path = frame_path(dir, preset.name, frame, "exr");
            outputs.stage(path, exr_bytes(image, path));
        }
        if (png) {
            const std::string path = frame_path(dir, preset.name, frame, "png");
            outputs.stage(path, png_bytes(image, path, exposure));
        }
        outputs.commit();
        made.keep = true;
        ++written;
        progress.frame_done(frame, std::to_string(scene.spheres.size()) + (scene.spheres.size() == 1 ? " sphere" : " spheres"));
        if (g_stop_requested) break;
    }
    progress.finish();

    if (device && device->validation_message_count() > 0) {
        for (const std::string& m : device->take_validation_messages()) std::fprintf(stderr, "%s\n", m.c_str());
        std::fprintf(stderr, "brume: error: the Vulkan validation layer reported problems (above)\n");
        return 3;
    }
    std::printf("wrote %d frame%s in %.1f s (simulation %.2f s) to %s\n", written, written == 1 ? "" : "s",
                progress.elapsed_seconds(), sim_s, dir.string().c_str());
    if (sim.skipped() > 0)
        std::printf("the particle budget (max_particles = %u) skipped %llu births\n", preset.timeline.max_particles,
                    static_cast<unsigned long long>(sim.skipped()));
    if (g_stop_requested) {
        std::fprintf(stderr, "brume: interrupted after %d frame%s; every written frame is complete%s\n", written,
                     written == 1 ? "" : "s", args.video.empty() ? "" : ", and no video was encoded");
        return 130;
    }
    if (!args.video.empty()) {
        // ffmpeg reads an image sequence through a printf-like pattern: a '%' of the folder or the
        // preset's name is written "%%", or the frames are not found (after every frame was rendered).
        std::string frames;
        for (const char c : (dir / preset.name).string()) frames += c == '%' ? "%%" : std::string(1, c);
        const fs::path log = dir / (preset.name + ".ffmpeg.log");
        try {
            encode_video(frames + ".%04d.png", range.first, written, preset.timeline.fps, args.video, log);
        } catch (const std::exception&) {
            if (!g_stop_requested) throw;
            // Ctrl-C reached ffmpeg too: its exit is the interrupt's, not a failure to report with a log.
            fs::remove(log, ec);
            std::fprintf(stderr, "brume: interrupted while encoding %s; every frame is complete, and the video was not "
                                 "written (any old one is kept)\n", args.video.c_str());
            return 130;
        }
        std::printf("wrote %s\n", args.video.c_str());
    }
    return 0;
}

}  // namespace brume::app
