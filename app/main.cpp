// The `brume` command: subcommands for rendering, benchmarking and inspecting devices.
// Every failure reaches the user as one line naming the problem and a non-zero exit status.
#include "app/bench_command.h"
#include "app/cli_util.h"
#include "app/play_command.h"
#include "app/preview_command.h"
#include "app/preview_window.h"
#include "app/render_command.h"
#include "app/standard_streams.h"
#include "app/vdb_command.h"
#include "render/atomic_file.h"
#include "render/image_io.h"
#include "render/methods/registry.h"
#include "render/methods/ppll.h"
#include "render/vk/device.h"
#include "render/vk/vk_check.h"
#include "sim/scene_file.h"

#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <cstring>
#include <string>
#include <new>

namespace {

int list_devices() {
    const auto devices = brume::vk::Device::enumerate();
    if (devices.empty()) std::printf("no Vulkan devices\n");
    // Numbered as --device '#N' picks them (two of the same GPU differ only by number).
    for (std::size_t i = 0; i < devices.size(); ++i)
        std::printf("#%zu %s (%s, Vulkan %u.%u)\n", i, devices[i].name.c_str(), devices[i].type.c_str(),
                    VK_API_VERSION_MAJOR(devices[i].api_version), VK_API_VERSION_MINOR(devices[i].api_version));
    return 0;
}

int list_methods() {
    for (const std::string& line : brume::method_listing()) std::printf("%s\n", line.c_str());
    return 0;
}

// One line of bounded length, whatever a library or a file put in the message: the parts that echo
// input are cut where they are made (toml_text::excerpt); this is the last guard.
int fail(const char* what) {
    // Its start and its end are kept: the end is the reason ("File name too long") after a long path.
    constexpr std::size_t kMaxMessage = 2000, kKeptEnd = 600;
    const std::size_t n = std::strlen(what);
    if (n <= kMaxMessage)
        std::fprintf(stderr, "brume: error: %s\n", what);
    else
        std::fprintf(stderr, "brume: error: %.*s ... (%zu bytes in all) ... %s\n", int(kMaxMessage - kKeptEnd), what, n,
                     what + n - kKeptEnd);
    return 1;
}

// Standard error closed (`2>&-`): the descriptor is given /dev/null, so that messages vanish as asked
// rather than the next file opened taking descriptor 2 (and the error lines), and an output named "-"
// can still move the command's own lines off standard output (app/standard_streams.cpp).
void give_closed_standard_error_a_sink() {
    if (::fcntl(STDERR_FILENO, F_GETFD) != -1 || errno != EBADF) return;
    const int fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (fd < 0 || fd == STDERR_FILENO) return;
    ::dup2(fd, STDERR_FILENO);  // dup2 clears close-on-exec on the copy
    ::close(fd);                // a lower descriptor (0 or 1) it took is closed again, as it was
}

int run(int argc, char** argv);

}  // namespace

int main(int argc, char** argv) {
    give_closed_standard_error_a_sink();
    // A file-size limit (ulimit -f) or a reader that closed its pipe would kill the process in the
    // middle of a write, with no message and a temporary file left: ignored, the write fails with
    // EFBIG or EPIPE and is reported as any failed write. (play and preview take SIGPIPE as a stop
    // request while they run: app/stop_signals.h.) Child processes get the defaults back
    // (app/process.cpp).
    std::signal(SIGXFSZ, SIG_IGN);
    std::signal(SIGPIPE, SIG_IGN);
    const int status = run(argc, argv);
    // What the command printed on standard output (a list, a help text, a log) must have arrived:
    // `brume devices > /dev/full` is a failure, as in coreutils. The output files are written and
    // checked by their own writers.
    // A reader that stopped reading (`brume methods | head -1`) is no error to report: the shell's status
    // for it, as if the signal had ended the process.
    errno = 0;
    std::cout.flush();
    const bool lost = std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout;
    if (!lost) return status;
    if (errno == EPIPE) return status != 0 ? status : 128 + SIGPIPE;
    std::fprintf(stderr, "brume: error: cannot write to standard output%s%s: its lines were lost\n",
                 errno != 0 ? ": " : "", errno != 0 ? std::strerror(errno) : "");
    return status != 0 ? status : 1;
}

namespace {

int run(int argc, char** argv) {
    // Named, so that the usage lines read "brume render ..." however it was started (a full path, a
    // symlink), and the bare `brume`'s help, printed before any parse, names it at all.
    CLI::App app{"Brume: exact volumetric particle rendering with per-pixel linked lists", "brume"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "brume " BRUME_VERSION);
    brume::app::RenderArgs render_args;
    brume::app::add_render_command(app, render_args);
    brume::app::PlayArgs play_args;
    brume::app::add_play_command(app, play_args);
    brume::app::PreviewArgs preview_args;
    brume::app::add_preview_command(app, preview_args);
    brume::app::BenchArgs bench_args;
    brume::app::add_bench_command(app, bench_args);
    brume::app::VdbInfoArgs vdb_info_args;
    brume::app::VdbImportArgs vdb_import_args;
    brume::app::add_vdb_commands(app, vdb_info_args, vdb_import_args);
    brume::app::VdbExportArgs vdb_export_args;
    brume::app::VdbSampleArgs vdb_sample_args;
    brume::app::add_vdb_export_commands(app, vdb_export_args, vdb_sample_args);
    app.add_subcommand("devices", "List the Vulkan devices Brume can use");
    app.add_subcommand("methods", "List the rendering methods and their settings");
    if (argc < 2) {  // a new user's first try: show what there is, as usage
        std::fprintf(stderr, "%s", app.help().c_str());
        return 2;
    }
    // CLI11 answers a mistyped subcommand with "A subcommand is required", which hides the typo.
    bool known = true;
    try {
        if (argv[1][0] != '-') app.get_subcommand(argv[1]);
    } catch (const CLI::OptionNotFound&) {
        known = false;
    }
    if (!known) {
        std::string names;
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
            names += (names.empty() ? "" : ", ") + sub->get_name();
        std::fprintf(stderr, "brume: error: unknown subcommand '%.80s'; the subcommands are %s (see brume --help)\n", argv[1],
                     names.c_str());
        return 2;
    }
    // `bench layers --help` shows the options of layers, not of every benchmark.
    if (std::string(argv[1]) == "bench" && argc > 2) {
        bool help = false;
        std::string which;
        for (int i = 2; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--help" || a == "-h") help = true;
            else if (which.empty() && !a.empty() && a[0] != '-') which = a;
        }
        if (help && !which.empty()) brume::app::restrict_bench_help(*app.get_subcommand("bench"), which);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Point to the help of the subcommand whose options were wrong, not to the whole tool's.
        std::string help = "brume";
        for (const CLI::App* sub = &app;;) {
            const std::vector<CLI::App*> parsed = sub->get_subcommands();
            if (parsed.empty()) break;
            sub = parsed.front();
            help += " " + sub->get_name();
        }
        std::fprintf(stderr, "brume: error: %s (see %s --help)\n", e.what(), help.c_str());
        return 2;
    }

    // An option given an empty value ("--frames ''", an unset variable in a farm script) would read as the
    // option left out, and quietly mean the default (every frame): refused, for every option alike.
    for (const CLI::App* sub = &app;;) {
        for (const CLI::Option* opt : sub->get_options()) {
            if (opt->count() == 0 || opt->get_items_expected_min() == 0) continue;  // not given, or a flag
            // vdb-import --albedo-grid "" is documented: "" names no grid, where leaving it out takes the file's.
            if (opt->get_name(false, true) == "--albedo-grid") continue;
            for (const std::string& value : opt->results())
                if (value.empty()) {
                    const std::string name = opt->get_positional() ? opt->get_name() : opt->get_name(false, true);
                    std::fprintf(stderr, "brume: error: %s: an empty value (leave the option out for the default) (see brume%s%s --help)\n",
                                 name.c_str(), sub == &app ? "" : " ", sub == &app ? "" : sub->get_name().c_str());
                    return 2;
                }
        }
        const std::vector<CLI::App*> parsed = sub->get_subcommands();
        if (parsed.empty()) break;
        sub = parsed.front();
    }

    // An output named by the file standard output is open on is written as "-" is (app/standard_streams.h).
    for (std::string* out : {&render_args.exr, &render_args.png, &render_args.stats, &play_args.video,
                             &vdb_import_args.output, &vdb_export_args.output, &vdb_sample_args.output})
        *out = brume::app::standard_output_alias(*out);

    try {
        if (app.got_subcommand("render")) return brume::app::run_render(render_args);
        if (app.got_subcommand("play")) return brume::app::run_play(play_args);
        if (app.got_subcommand("preview")) return brume::app::run_preview(preview_args);
        if (app.got_subcommand("bench")) return brume::app::run_bench(bench_args);
        if (app.got_subcommand("vdb-info")) return brume::app::run_vdb_info(vdb_info_args);
        if (app.got_subcommand("vdb-import")) return brume::app::run_vdb_import(vdb_import_args);
        if (app.got_subcommand("vdb-export")) return brume::app::run_vdb_export(vdb_export_args);
        if (app.got_subcommand("vdb-sample")) return brume::app::run_vdb_sample(vdb_sample_args);
        if (app.got_subcommand("devices")) return list_devices();
        if (app.got_subcommand("methods")) return list_methods();
    } catch (const brume::app::UsageError& e) {
        fail(e.what());
        return 2;  // a bad command line, as CLI11's own errors
    } catch (const brume::app::PreviewUnavailable& e) {
        return fail(e.what());
    } catch (const brume::SceneFileError& e) {
        return fail(e.what());
    } catch (const brume::ImageIoError& e) {
        return fail(e.what());
    } catch (const brume::FileWriteError& e) {
        return fail(e.what());
    } catch (const brume::PoolBudgetError& e) {
        return fail(e.what());
    } catch (const brume::vk::VulkanError& e) {
        // The raw call and source line mean nothing to a user who asked for a large frame.
        if (const char* advice = brume::vk::out_of_memory_advice(e.result())) return fail(advice);
        return fail(e.what());
    } catch (const std::bad_alloc&) {
        return fail("out of host memory: this run needs more than the machine, or its limit on this process, "
                    "gives; try a smaller --size, scene or grid");
    } catch (const std::exception& e) {
        return fail(e.what());
    }
    return 0;
}

}  // namespace
