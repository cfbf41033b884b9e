#include "app/preview_command.h"

#include "app/cli_util.h"
#include "app/preview_adaptive.h"
#include "app/preview_controls.h"
#include "app/preview_edit.h"
#include "app/preview_image_presenter.h"
#include "app/preview_imgui.h"
#include "app/preview_panel.h"
#include "app/preview_pending_edit.h"
#include "app/preview_reference.h"
#include "app/preview_reload.h"
#include "app/preview_renderer.h"
#include "app/preview_script.h"
#include "app/preview_script_runner.h"
#include "app/preview_sequence.h"
#include "app/preview_session.h"
#include "app/preview_window.h"
#include "app/standard_streams.h"
#include "app/stop_signals.h"
#include "render/atomic_file.h"
#include "render/frame/swapchain_presenter.h"
#include "render/methods/registry.h"
#include "render/vk/device.h"
#include "sim/builtin_presets.h"
#include "sim/vdb/volume_loader.h"

#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <optional>
#include <utility>
#include <unistd.h>

namespace brume::app {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Without --size the window is the preset's resolution, enlarged by a whole factor to be at least 800
// pixels wide: what `brume play` renders, shown at a size one can work with.
void default_viewport(const Preset& preset, int& width, int& height) {
    const int w = preset.scene.camera.width, h = preset.scene.camera.height;
    const int factor = std::max(1, (800 + w - 1) / w);
    width = w * factor;
    height = h * factor;
}

// Smoothed per-part wall-clock times for the panel, and for the summary a scripted run prints, a
// tally of the frames since the internal resolution last changed (the figures it settled on).
struct Timing {
    PartTimes smoothed;
    PartTimes total;
    int frames = 0;
    VkExtent2D tallied_extent{};
    void add(const PartTimes& t, VkExtent2D internal) {
        if (internal.width != tallied_extent.width || internal.height != tallied_extent.height) {
            total = {};
            frames = 0;
            tallied_extent = internal;
        }
        auto blend = [](double& s, double v) { s = s == 0.0 ? v : 0.9 * s + 0.1 * v; };
        blend(smoothed.simulate, t.simulate);
        blend(smoothed.upload, t.upload);
        blend(smoothed.render, t.render);
        blend(smoothed.ui, t.ui);
        blend(smoothed.present, t.present);
        blend(smoothed.frame, t.frame);
        total.simulate += t.simulate;
        total.upload += t.upload;
        total.render += t.render;
        total.ui += t.ui;
        total.present += t.present;
        total.frame += t.frame;
        ++frames;
    }
};

// The editor for `set`, over the text the preset was read from: the file, or the built-in's text.
std::unique_ptr<PresetEditor> make_editor(const std::string& name_or_path) {
    std::error_code ec;
    if (fs::is_regular_file(name_or_path, ec)) {
        std::ifstream in(name_or_path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        return std::make_unique<PresetEditor>(text.str(), name_or_path);
    }
    const std::optional<std::string_view> text = builtin_preset_toml(name_or_path);
    if (!text) throw std::invalid_argument("no preset text for " + name_or_path);
    return std::make_unique<PresetEditor>(std::string(*text), "presets/" + name_or_path + ".toml");
}

}  // namespace

void add_preview_command(CLI::App& app, PreviewArgs& args) {
    CLI::App* cmd = app.add_subcommand("preview", "Open a window that plays a preset, with a timeline and a panel");
    cmd->add_option("preset", args.preset, "Preset or scene file, or built-in name (brume play --list); none: the default");
    cmd->add_option("--size", args.size, "Viewport size WxH (default: the preset's resolution, enlarged)");
    cmd->add_option("--method", args.method, "NAME[:SETTING] of a GPU method (default: the preset's)");
    cmd->add_option("--exposure", args.exposure, "Exposure in stops (default: the preset's)")
        ->each([&args](const std::string&) { args.exposure_set = true; });
    cmd->add_option("--frame", args.frame, "Open at frame N (0-based)");
    cmd->add_option("--screenshot", args.screenshot,
                    "With --frame: save that frame's viewport (.png as brume play writes it, or .exr linear) and exit");
    cmd->add_option("--script", args.script, "Run the commands of FILE (docs/preview.md), then stay open unless it quits");
    cmd->add_flag("--fixed-resolution", args.fixed_resolution, "Always render at the full viewport size");
    cmd->add_option("--device", args.device, "Vulkan device (a substring of its name, or #N as brume devices numbers them; default lavapipe)");
    cmd->add_flag("--validate", args.validate, "Enable the Vulkan validation layers; any message fails the run");
    cmd->add_option("--max-memory", args.max_memory, "Node-pool budget, e.g. 256M");
}

int run_preview(const PreviewArgs& args, PreviewFigures* figures) {
    std::atomic<bool> stopped_by_signal{false};
    // Everything that can be refused is refused before a window opens.
    if (args.preset == kStandardInputName)  // render and play read it; the preview edits and reloads a file
        throw UsageError("preview - : the preview watches, reloads and saves its preset, so it needs a file, not "
                         "standard input (save it to a file and open that)");
    Preset preset = resolve_preset(args.preset.empty() ? default_preset_name() : args.preset);
    int width = 0, height = 0;
    if (!args.size.empty())
        parse_size(args.size, width, height);
    else
        default_viewport(preset, width, height);
    preset.scene.camera.width = width;
    preset.scene.camera.height = height;
    const std::string method = args.method.empty() ? preset.render.method : args.method;
    const double exposure = args.exposure_set ? args.exposure : preset.render.exposure;
    if (!std::isfinite(exposure)) throw UsageError("--exposure must be a finite number of stops");
    MethodOptions options;
    unsigned given = 0;
    if (!args.max_memory.empty()) {
        options.max_pool_bytes = parse_bytes(args.max_memory);
        given |= kHonoursMaxMemory;
    }
    check_method_usage(method, given);
    if (!find_method(method).needs_device)
        throw UsageError("--method " + method + " runs on the CPU; the preview shows GPU methods "
                         "(render it with brume play --method " + method + ")");
    if (args.frame >= preset.timeline.frame_count())
        throw UsageError("--frame " + std::to_string(args.frame) + " is outside the preset's frames 0-" +
                         std::to_string(preset.timeline.frame_count() - 1));
    if (args.frame < -1) throw UsageError("--frame must be 0 or more");
    if (!args.screenshot.empty()) {
        if (args.frame < 0) throw UsageError("--screenshot needs --frame N (the frame to save)");
        if (!args.screenshot.ends_with(".png") && !args.screenshot.ends_with(".exr"))
            throw UsageError("--screenshot " + args.screenshot + ": the name must end in .png or .exr");
        if (!args.script.empty()) throw UsageError("--screenshot and --script: put the screenshot in the script");
        check_writable_path(args.screenshot);
    }
    std::vector<ScriptCommand> commands;
    if (!args.script.empty()) commands = load_script(args.script);
    if (!args.screenshot.empty()) {
        ScriptCommand shot;
        shot.kind = ScriptCommand::Kind::Screenshot;
        shot.text = args.screenshot;
        shot.where = "--screenshot";
        ScriptCommand quit;
        quit.where = "--screenshot";
        commands = {shot, quit};
    }
    const bool scripted = !commands.empty();
    std::unique_ptr<PresetEditor> editor = make_editor(args.preset.empty() ? default_preset_name() : args.preset);
    for (const VolumeReport& v : prepare_preset(preset)) print_volume_report(v);
    // An edited preset is read from text: give it what load_preset_file and run_preview gave the first.
    std::string base_dir;
    if (std::error_code ec; fs::is_regular_file(args.preset, ec)) base_dir = fs::path(args.preset).parent_path().string();
    const std::function<void(Preset&)> prepare_edit = [&](Preset& p) {
        for (VdbVolume& v : p.scene.volumes) v.source.base_dir = base_dir;
        for (EmitterDesc& e : p.emitters)
            if (e.shape == EmitterShape::Density) e.density_source.base_dir = base_dir;
        p.scene.camera.width = width;
        p.scene.camera.height = height;
        for (const VolumeReport& v : prepare_preset(p)) print_volume_report(v);
    };

    PreviewWindow window(width, height, "brume preview: " + preset.name);
    vk::DeviceOptions device_options;
    device_options.device_name = args.device;
    device_options.validate = args.validate;
    device_options.instance_extensions = window.required_instance_extensions();
    device_options.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    device_options.create_surface = [&window](VkInstance instance) { return window.create_surface(instance); };
    vk::Device device(device_options);

    int shown_frames = 0;
    int last_frame = 0;
    AdaptiveResolution adaptive;
    adaptive.set_enabled(!args.fixed_resolution);
    Timing timing;
    // The window's presents, to show that a slow frame does not hold it (docs/preview.md).
    struct Presents {
        std::uint64_t count = 0;
        std::uint64_t while_rendering = 0;  // presents made while the render thread had a frame
        double longest_gap_ms = 0.0;        // the longest time between two presents
        std::uint64_t frames_rendered = 0;
        std::uint64_t polls = 0;            // turns of the loop, each polling the window's events
        double longest_poll_gap_ms = 0.0;   // the longest time between two polls (waits for events included)
    } presents;
    VkExtent2D internal{};
    VkExtent2D last_viewport{};
    {
        PreviewSession session(device, preset, method, options, exposure);
        if (args.frame >= 0) session.timeline().seek(int(args.frame));
        session.playback().one_frame_per_view = scripted;
        SwapchainPresenter presenter(device, window.framebuffer_extent());
        // The queue present waits for the tone map's fence (below): this thread never waits for the queue.
        presenter.set_deferred_present(true);
        PreviewImgui ui(window.handle(), device, presenter.render_pass(), vk::FrameRing::kDefaultSlots);
        presenter.set_overlay([&ui](VkCommandBuffer cmd) { ui.record(cmd); });
        ScriptRunner script(std::move(commands));
        bool panel_visible = true;
        PanelState panel{session, adaptive, timing.smoothed};
        // A file given on the command line is watched; a built-in preset cannot change.
        std::optional<PresetWatcher> watcher;
        if (std::error_code ec; !args.preset.empty() && fs::is_regular_file(args.preset, ec)) {
            watcher.emplace(args.preset, width, height);
            panel.watched_file = args.preset;
        }
        // The frame path runs on the render thread; this thread shows its last finished frame
        // (docs/preview.md, "What runs beside the frame"). Declared after the presenter and the UI,
        // so it stops first.
        PreviewRenderer renderer(device, [] { PreviewWindow::wake(); });
        ImagePresenter shown_frame(device);
        ReferenceCheck reference;
        // "Error against the reference": the method's frame at the reduced size is rendered on the
        // render thread (a job), then the reference starts on its worker with it.
        struct ReferenceFrame {
            std::uint64_t job = 0;
            Scene scene;
            int frame = 0;
            std::string method;
        };
        std::optional<ReferenceFrame> reference_frame;
        const std::function<void()> start_reference = [&] {
            if (reference.running() || reference_frame) return;
            const VkExtent2D viewport = window.framebuffer_extent();
            int w = 0, h = 0;
            ReferenceCheck::reduced_size(int(std::max(1u, viewport.width)), int(std::max(1u, viewport.height)), w, h);
            FrameRequest request = session.frame_request(std::uint32_t(w), std::uint32_t(h), true);
            request.compare = CompareMode::Off;
            request.heat_map = nullptr;
            request.want_stats = false;
            ReferenceFrame pending{0, request.scene, session.timeline().frame(), session.method_spec()};
            pending.job = renderer.request_job(std::move(request));
            reference_frame = std::move(pending);
        };
        // Polls both halves; true while either runs.
        const std::function<bool()> reference_busy = [&] {
            if (reference_frame) {
                std::optional<RenderedFrame> done = renderer.take_job(reference_frame->job);
                if (!done) return true;
                if (!done->error.empty()) throw std::runtime_error(done->error);
                reference.start(reference_frame->scene, std::move(done->image), reference_frame->frame,
                                reference_frame->method);
                reference_frame.reset();
            }
            reference.poll();
            return reference.running();
        };
        panel.reference = &reference;
        panel.start_reference = start_reference;
        // Render sequence: brume play itself, with the options the view has (app/preview_sequence.h).
        SequenceRender sequence;
        const std::string opened = args.preset.empty() ? default_preset_name() : args.preset;
        const auto start_sequence = [&](const std::string& dir, int first, int last, const std::string& formats) {
            if (sequence.running()) throw std::runtime_error("a sequence is still rendering");
            std::string preset_arg = opened;
            fs::path temporary;
            if (editor->edited()) {
                // The edits, written as Save writes them, beside the opened file so that its relative
                // paths (grids) resolve as they do for it; the preset's name is in the text.
                std::error_code ec;
                temporary = fs::is_regular_file(opened, ec)
                                ? fs::path(opened).parent_path() / ("." + fs::path(opened).stem().string() + ".preview-sequence.toml")
                                : fs::temp_directory_path() / ("brume-preview-" + std::to_string(::getpid()) + "-" + opened + ".toml");
                // A name taken from the file's stem would be the hidden file's: the frames are named by
                // the preset's name, so it is written into the copy ([preset] name, added if missing).
                PresetEditor named(editor->saved_text(), temporary.string());
                named.set("preset.name", "\"" + session.timeline().preset().name + "\"");
                write_file_atomically(temporary.string(), named.saved_text());
                preset_arg = temporary.string();
            }
            const VkExtent2D viewport = window.framebuffer_extent();
            char exposure_text[40];
            std::snprintf(exposure_text, sizeof exposure_text, "%.17g", session.exposure());
            std::vector<std::string> play{preset_arg, "--output", dir, "--frames", std::to_string(first) + "-" + std::to_string(last),
                                          "--size", std::to_string(viewport.width) + "x" + std::to_string(viewport.height),
                                          "--method", session.method_spec(), "--exposure", exposure_text, "--format", formats};
            if (!args.device.empty()) play.insert(play.end(), {"--device", args.device});
            if (!args.max_memory.empty()) play.insert(play.end(), {"--max-memory", args.max_memory});
            if (args.validate) play.push_back("--validate");
            sequence.start(play, last - first + 1, temporary);
        };
        panel.sequence = &sequence;
        panel.start_sequence = [&](const std::string& dir, int first, int last, const std::string& formats) -> std::string {
            try {
                start_sequence(dir, first, last, formats);
                return {};
            } catch (const std::exception& e) {
                return e.what();
            }
        };
        PendingEdit pending_edit;
        std::string pending_edit_error;
        const auto submit_edit = [&](Preset edited, const std::string& key) {
            if (preparing_is_slow(edited)) {
                pending_edit_error.clear();
                pending_edit.start(std::move(edited), key, prepare_edit);
                return true;
            }
            try {
                prepare_edit(edited);
            } catch (...) {
                editor->return_to_shown();  // refused: the editor (the panel's values, Save) keeps what is shown
                throw;
            }
            session.apply_edit(edited, key);
            editor->keep_shown();
            return false;
        };
        panel.preset_edit.preparing = [&pending_edit] { return pending_edit.busy(); };
        ScriptTargets targets{session,         renderer,       window,         presenter,     panel_visible,
                              watcher ? &*watcher : nullptr,   editor,         prepare_edit,  panel.preset_edit.stale,
                              reference,       start_reference, reference_busy, sequence,     start_sequence,
                              submit_edit,     pending_edit,   pending_edit_error};
        panel.preset_edit.read = [&editor] { return editor->values(); };
        panel.preset_edit.set = [&](const std::string& key, const std::string& value) -> std::string {
            try {
                submit_edit(editor->set(key, value), key);
                return {};
            } catch (const std::exception& e) {
                return e.what();
            }
        };
        // Save goes to the file opened, or for a built-in preset to NAME.toml here.
        std::error_code exists_error;
        panel.preset_edit.save_path = fs::is_regular_file(args.preset, exists_error)
                                          ? args.preset
                                          : (args.preset.empty() ? default_preset_name() : args.preset) + ".toml";
        panel.preset_edit.save = [&]() -> std::string {
            try {
                if (pending_edit.busy()) return "save: an edit is still being prepared; save once the view shows it";
                editor->save(panel.preset_edit.save_path);
                return {};
            } catch (const std::exception& e) {
                return e.what();
            }
        };
        // The method list starts at the method shown.
        for (const MethodEntry& m : method_catalogue()) {
            if (m.name == find_method(method).name) break;
            if (m.needs_device) ++panel.method_index;
        }
        const std::size_t colon = method.find(':');
        std::snprintf(panel.method_setting, sizeof panel.method_setting, "%s",
                      colon == std::string::npos ? find_method(method).default_setting.c_str()
                                                 : method.substr(colon + 1).c_str());

        int quiet_frames = 0;
        std::uint64_t events_seen = 0;
        const auto run_start = Clock::now();
        auto last = run_start;
        // What was last asked of the render thread, so that a view is asked for again only when it changed.
        struct ViewKey {
            std::uint64_t generation = 0;  // PreviewSession::view_generation()
            int frame = 0;
            std::uint32_t width = 0, height = 0;
            bool list_stats = false;
            bool operator==(const ViewKey&) const = default;
        };
        std::optional<ViewKey> requested_key;
        std::uint64_t requested_id = 0;  // the view asked for last
        bool requested_shown = false;    // ... and it has been presented
        std::uint64_t shown_id = 0;      // the view the window shows
        // A finished view presented for the first time adds its figures to the timing.
        struct FreshFrame {
            double upload_ms = 0.0, render_ms = 0.0;
            VkExtent2D extent{};
            int frame = 0;
        };
        std::optional<FreshFrame> fresh;
        double simulate_ms = 0.0;  // since the last fresh frame shown
        bool moved_since = false;  // the view moved since the last fresh frame shown
        auto last_fresh = run_start;
        auto last_present = run_start;  // the last tone map submitted
        auto last_queued = run_start;   // the last queue present
        // The same frame is presented again at most at the display's rate (60 Hz) while input comes, and
        // 10 times a second otherwise (the panel's figures): on lavapipe a present is CPU time that
        // the render thread's frame would otherwise have.
        constexpr double kDisplayInterval = 1.0 / 60.0;
        constexpr double kIdleInterval = 1.0 / 10.0;
        std::uint64_t events_at_present = 0;
        // A signal closes the window as Esc does, so that a render-sequence's child stops and its
        // temporary files go (their owners' destructors), then the preview exits 130.
        const StopSignals stop_signals(stopped_by_signal);
        while (!window.should_close() && !stopped_by_signal) {
            const auto frame_start = Clock::now();
            const double dt = std::chrono::duration<double>(frame_start - last).count();
            last = frame_start;
            if (presents.polls++ > 0) presents.longest_poll_gap_ms = std::max(presents.longest_poll_gap_ms, dt * 1000.0);
            window.poll_events();
            // The frame submitted last goes to the screen once its tone map is done: then the queue
            // present has nothing to wait for (SwapchainPresenter::set_deferred_present).
            // Try-locked: the render thread holds the queue's lock through a vkDeviceWaitIdle when its
            // targets change size (FrameResources::upload), and this thread does not wait for that.
            std::unique_lock<std::recursive_mutex> flush_lock;
            if (presenter.has_deferred_present() && shown_frame.ready() &&
                (flush_lock = device.try_lock_queue()).owns_lock()) {
                presenter.present_deferred();
                flush_lock.unlock();
                const auto now = Clock::now();
                if (presents.count > 0)
                    presents.longest_gap_ms = std::max(presents.longest_gap_ms,
                                                       std::chrono::duration<double, std::milli>(now - last_queued).count());
                ++presents.count;
                if (renderer.busy()) ++presents.while_rendering;
                last_queued = now;
            }
            // While a present waits for its tone map, waits are short.
            const double longest_wait = presenter.has_deferred_present() ? 0.002 : 1.0;
            const VkExtent2D viewport = window.framebuffer_extent();
            presenter.set_window_extent(viewport);
            last_viewport = viewport;
            if (viewport.width == 0 || viewport.height == 0) {
                window.wait_events();  // minimised: no swapchain, nothing to draw
                continue;
            }
            if (watcher) {
                std::string error;
                if (std::optional<Preset> reloaded = watcher->poll(seconds_since(run_start), error)) {
                    pending_edit.discard();  // edits of the old text no longer apply
                    session.replace_preset(*reloaded);
                    editor = make_editor(args.preset);  // edits start again from the file
                    panel.preset_edit.stale = true;
                    panel.preset_edit.error.clear();
                    quiet_frames = 0;
                    panel.reload_error.clear();
                    std::printf("reloaded %s\n", args.preset.c_str());
                } else if (!error.empty()) {
                    std::fprintf(stderr, "brume: reload refused, still playing the last good version: %s\n", error.c_str());
                    panel.reload_error = error;
                    quiet_frames = 0;
                }
                std::fflush(stdout);
                std::fflush(stderr);
            }
            if (pending_edit.busy()) {
                quiet_frames = 0;  // the panel says it is preparing, and the view changes when it is done
                if (std::optional<std::pair<Preset, std::string>> done = pending_edit.poll(pending_edit_error)) {
                    session.apply_edit(done->first, done->second);
                    editor->keep_shown();
                    panel.preset_edit.stale = true;
                } else if (!pending_edit_error.empty()) {
                    panel.preset_edit.error = pending_edit_error;
                    if (!pending_edit.busy()) {
                        editor->return_to_shown();  // the refused edit is not saved, and the panel shows its old value
                        panel.preset_edit.stale = true;
                    }
                }
            }
            // The render thread's newest finished view becomes the frame shown.
            if (std::optional<RenderedFrame> done = renderer.take_view(); done && !done->error.empty()) {
                // A frame the scene cannot give (a camera path through an undefined view) is said in the
                // panel and on stderr, once, while the window plays on; a script stops on it.
                if (!done->refused || scripted) throw std::runtime_error(done->error);
                if (panel.view_error != done->error)
                    std::fprintf(stderr, "brume: frame %d not shown: %s\n", done->frame, done->error.c_str());
                panel.view_error = done->error;
                quiet_frames = 0;
            } else if (done) {
                panel.view_error.clear();
                session.last_stats() = done->stats;
                if (session.heat_map()) session.set_heat_figures(done->heat);
                fresh = FreshFrame{done->upload_ms, done->render_ms,
                                   {std::uint32_t(done->image.width), std::uint32_t(done->image.height)}, done->frame};
                shown_frame.set_image(std::move(done->image));
                shown_id = done->id;
                quiet_frames = 0;
            }
            // A scripted run moves on (its commands, playback) only once the frame it asked for is
            // shown, as if each frame were rendered at once: the same frames on any machine, and a
            // `screenshot` or `capture` of the state the script set. The window keeps presenting the
            // last frame and polling events meanwhile.
            const bool waiting_for_view = scripted && requested_id != 0 && !requested_shown;
            if (!waiting_for_view && !script.run(targets)) break;
            if (reference.running() || reference_frame) {
                reference_busy();
                quiet_frames = 0;  // the panel shows the result when it comes
            }
            if (sequence.running()) {
                const int before = sequence.frames_done();
                sequence.poll();
                // The panel's progress moves when a frame is written (and when the run ends).
                if (sequence.frames_done() != before || !sequence.running()) quiet_frames = 0;
            }

            const int frame_before = session.timeline().frame();
            const WindowInput input = window.take_input();
            bool moved = apply_controls(input, ui.wants_mouse(), ui.wants_keyboard(), dt, window, session);
            auto t = Clock::now();
            if (!waiting_for_view) session.advance(dt);
            simulate_ms += seconds_since(t) * 1000.0;
            moved = moved || session.playback().playing || session.timeline().frame() != frame_before;
            moved_since = moved_since || moved;
            // A script blocked on a reload, a sequence or a worker leaves a still view quiet: it was
            // re-rendered and presented all the while (58 identical frames beside a 48-frame sequence,
            // which took twice as long as play alone).
            const bool script_steps = script.active() && !script.blocked();
            if (window.event_count() != events_seen || moved || script_steps) quiet_frames = 0;
            events_seen = window.event_count();

            // Ask the render thread for the view when it changed (the newest request replaces one not
            // begun: latest wins), and while the adaptive resolution refines a still view. A scripted
            // run asks for a frame at every step, as the loop rendered one per step before, so that
            // `wait N` is N frames rendered and shown.
            internal = adaptive.internal_extent(viewport);
            const ViewKey key{session.view_generation(), session.timeline().frame(), internal.width, internal.height,
                              panel.list_stats};
            const bool refining = internal.width != viewport.width && requested_shown && !renderer.busy();
            if (!waiting_for_view && ((scripted && !script.blocked()) || key != requested_key || refining)) {
                FrameRequest request = session.frame_request(internal.width, internal.height, panel.list_stats);
                request.frame = session.timeline().frame();
                requested_id = renderer.request_view(std::move(request));
                requested_key = key;
                requested_shown = false;
            }

            // A still view with nothing to do waits for input (or for the render thread's finished
            // frame, which wakes it) instead of redrawing the same frame; a few frames after the last
            // event still run, for the UI's hover and click states to settle.
            if (!fresh && quiet_frames >= 3) {
                if (longest_wait < 1.0)
                    window.wait_events_for(longest_wait);
                else
                    window.wait_events();
                continue;
            }
            // The same frame again: at most at the rates above.
            const double interval = window.event_count() != events_at_present ? kDisplayInterval : kIdleInterval;
            if (!fresh && seconds_since(last_present) < interval) {
                window.wait_events_for(std::min({longest_wait, kDisplayInterval, interval - seconds_since(last_present)}));
                continue;
            }
            // Never wait for the GPU here: when the last present is still on the queue, or the render
            // thread is submitting (lavapipe runs a submission inside vkQueueSubmit), this turn
            // presents nothing and the loop goes on polling events.
            if (!shown_frame.has_image() || !shown_frame.ready()) {
                window.wait_events_for(0.002);
                continue;
            }
            std::unique_lock<std::recursive_mutex> queue = device.try_lock_queue();
            if (!queue.owns_lock()) {
                window.wait_events_for(0.002);
                continue;
            }
            ++quiet_frames;

            PartTimes part;
            t = Clock::now();
            ui.new_frame();
            panel.viewport = viewport;
            panel.internal = fresh ? fresh->extent : internal;
            if (panel_visible) draw_panel(panel);
            ui.render();
            part.ui = seconds_since(t) * 1000.0;

            presenter.set_exposure(session.exposure());
            const bool first_of_current = shown_id == requested_id && !requested_shown;
            if (first_of_current && script.wants_capture()) presenter.capture_next_frame();
            t = Clock::now();
            const bool shown = shown_frame.present(presenter);
            part.present = seconds_since(t) * 1000.0;
            queue.unlock();
            if (!shown) continue;
            const auto now = Clock::now();
            if (!presenter.has_deferred_present()) {  // a captured frame is presented at once
                ++presents.count;
                last_queued = now;
            }
            last_present = now;
            events_at_present = window.event_count();
            if (fresh) {
                // A frame shown for the first time: the view's frame rate and the parts of its frame.
                ++shown_frames;
                last_frame = fresh->frame;
                part.simulate = simulate_ms;
                part.upload = fresh->upload_ms;
                part.render = fresh->render_ms;
                part.frame = std::chrono::duration<double, std::milli>(now - last_fresh).count();
                timing.add(part, fresh->extent);
                adaptive.frame_done(part.frame / 1000.0, moved_since);
                internal = fresh->extent;
                last_fresh = now;
                simulate_ms = 0.0;
                moved_since = false;
                fresh.reset();
            }
            if (first_of_current) {
                requested_shown = true;
                script.frame_shown(presenter);
            }
        }
        presents.frames_rendered = renderer.frames_rendered();
    }

    if (device.validation_message_count() > 0) {
        for (const std::string& m : device.take_validation_messages()) std::fprintf(stderr, "%s\n", m.c_str());
        std::fprintf(stderr, "brume: error: the Vulkan validation layer reported problems (above)\n");
        return 3;
    }
    if (stopped_by_signal) {
        std::fprintf(stderr, "brume: preview interrupted by a signal; closed as Esc closes it\n");
        return 130;
    }
    if (scripted && timing.frames > 0) {
        const double n = timing.frames;
        std::printf("preview: %d frames shown; the last %d at internal resolution %ux%u of %ux%u: %.1f FPS, mean ms "
                    "per frame: simulate %.2f, upload %.2f, render %.2f, ui %.2f, present %.2f\n",
                    shown_frames, timing.frames, timing.tallied_extent.width, timing.tallied_extent.height,
                    last_viewport.width, last_viewport.height, 1000.0 * n / timing.total.frame,
                    timing.total.simulate / n, timing.total.upload / n, timing.total.render / n, timing.total.ui / n,
                    timing.total.present / n);
        std::printf("preview: the window presented %llu times, %llu of them while the render thread had a frame; "
                    "%llu frames rendered; the longest time between two presents %.1f ms; events polled %llu times, "
                    "at most %.1f ms apart\n",
                    static_cast<unsigned long long>(presents.count), static_cast<unsigned long long>(presents.while_rendering),
                    static_cast<unsigned long long>(presents.frames_rendered), presents.longest_gap_ms,
                    static_cast<unsigned long long>(presents.polls), presents.longest_poll_gap_ms);
        if (figures) {
            figures->shown_frames = shown_frames;
            figures->tallied_frames = timing.frames;
            figures->last_frame = last_frame;
            figures->internal_width = timing.tallied_extent.width;
            figures->internal_height = timing.tallied_extent.height;
            figures->viewport_width = last_viewport.width;
            figures->viewport_height = last_viewport.height;
            figures->fps = 1000.0 * n / timing.total.frame;
            figures->simulate_ms = timing.total.simulate / n;
            figures->upload_ms = timing.total.upload / n;
            figures->render_ms = timing.total.render / n;
            figures->ui_ms = timing.total.ui / n;
            figures->present_ms = timing.total.present / n;
            figures->frame_ms = timing.total.frame / n;
        }
    }
    return 0;
}

}  // namespace brume::app
