// A bounded, seeded fuzz run of the brume binary itself (the reliability contract in README.md, "Bad
// input"): mutations of every shipped preset, test scene and example (tests/fuzz_mutations.h) are
// rendered by `brume render` in a child process, over an output that already exists. Each run must
//   - end by itself, within a per-case limit (no hang), and not by a signal (no crash);
//   - succeed and write a well-formed EXR with nothing on stderr but `brume:` lines and no validation
//     message, or
//   - fail with exactly one `brume: error: ` line of bounded length and leave the existing output
//     byte-identical, with no temporary file left beside it.
// tests/test_fuzz_inputs.cpp runs thousands of mutations through the readers in-process; this one
// proves the same inputs through everything after them (simulation, device, writers), which an
// in-process parser test cannot. A failure names the case's file and index: the run is seeded, so
// it reproduces, and the failing input is kept in the scratch folder.
#include "fuzz_mutations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace brume {
namespace {

namespace fs = std::filesystem;

constexpr int kMutationsPerFile = 12;  // 22 inputs: 264 runs, about 25 s on the 2-core machine
constexpr double kCaseLimitSeconds = 30.0;     // a run longer than this is a hang
constexpr std::size_t kMaxErrorBytes = 2100;   // "brume: error: " plus a bounded message (docs/decisions.md)
const std::string kSentinel = "existing output: a failed run must leave these bytes as they are\n";

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << bytes;
}

struct Outcome {
    bool timed_out = false;
    bool signalled = false;
    int signal = 0;
    int status = -1;
    std::string stderr_text;
};

// Runs brume with `args` in `dir`, stdout and stderr to files there, killed after kCaseLimitSeconds.
Outcome run_brume(const fs::path& dir, const std::vector<std::string>& args) {
    std::vector<std::string> argv_text{BRUME_BINARY};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    const fs::path out_path = dir / "stdout", err_path = dir / "stderr";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    Outcome outcome;
    if (posix_spawn(&pid, BRUME_BINARY, &actions, nullptr, argv.data(), environ) != 0) {
        posix_spawn_file_actions_destroy(&actions);
        ADD_FAILURE() << "cannot start " << BRUME_BINARY;
        return outcome;
    }
    posix_spawn_file_actions_destroy(&actions);
    const auto start = std::chrono::steady_clock::now();
    int wstatus = 0;
    for (;;) {
        const pid_t r = waitpid(pid, &wstatus, WNOHANG);
        if (r == pid) break;
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > kCaseLimitSeconds) {
            outcome.timed_out = true;
            kill(pid, SIGKILL);
            waitpid(pid, &wstatus, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!outcome.timed_out) {
        if (WIFSIGNALED(wstatus)) {
            outcome.signalled = true;
            outcome.signal = WTERMSIG(wstatus);
        } else {
            outcome.status = WEXITSTATUS(wstatus);
        }
    }
    outcome.stderr_text = read(err_path);
    return outcome;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

// Every entry of `dir` but the runner's own stdout and stderr.
std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

bool is_exr(const std::string& bytes) { return bytes.size() > 4 && bytes.compare(0, 4, "\x76\x2f\x31\x01") == 0; }

TEST(FuzzCli, EveryMutatedInputRendersOrFailsCleanlyAndKeepsTheExistingOutput) {
    const std::vector<fuzz::Input> files = fuzz::inputs(BRUME_SOURCE_DIR);
    ASSERT_GE(files.size(), 20u) << "the shipped presets and test scenes were not found under " << BRUME_SOURCE_DIR;
    // Only lavapipe, with the validation layer on, as in every GPU test (tests/gpu_test_env.h).
    setenv("VK_DRIVER_FILES", "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json", 1);
    setenv("VK_ICD_FILENAMES", "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json", 1);
    setenv("BRUME_VALIDATE", "1", 1);
    setenv("BRUME_CACHE", "off", 1);
    const fs::path scratch = fs::path(BRUME_SCRATCH_DIR) / "fuzz_cli";
    fs::remove_all(scratch);
    std::mt19937_64 rng(14);  // seeded: a failure reproduces
    const auto start = std::chrono::steady_clock::now();
    int cases = 0, rendered = 0, refused = 0;
    for (const fuzz::Input& input : files) {
        const std::string original = read(input.path);
        for (int k = 0; k < kMutationsPerFile; ++k) {
            const std::string name = input.path.stem().string() + "." + std::to_string(k);
            const fs::path dir = scratch / name, out_dir = dir / "out";
            fs::create_directories(out_dir);
            // The mutated file keeps its name: a preset's `name` must match it.
            const fs::path scene = dir / input.path.filename();
            write(scene, fuzz::mutate(original, rng));
            write(out_dir / "out.exr", kSentinel);
            std::vector<std::string> args{"render", scene.string(), "--size", "8x6", "-o", (out_dir / "out.exr").string()};
            if (input.preset) args.insert(args.begin() + 2, {"--frame", "0"});
            const Outcome o = run_brume(dir, args);
            ++cases;
            const std::string where = name + " (" + scene.string() + ")";
            const std::vector<std::string> err = lines(o.stderr_text);
            bool clean = true;
            if (o.timed_out) {
                ADD_FAILURE() << where << ": still running after " << kCaseLimitSeconds << " s";
                clean = false;
            } else if (o.signalled) {
                ADD_FAILURE() << where << ": killed by signal " << o.signal;
                clean = false;
            } else if (o.status == 0) {
                ++rendered;
                if (!is_exr(read(out_dir / "out.exr"))) {
                    ADD_FAILURE() << where << ": exit 0, but out.exr is not an EXR";
                    clean = false;
                }
                for (const std::string& line : err)
                    if (line.rfind("brume: ", 0) != 0 || line.find("VUID") != std::string::npos) {
                        ADD_FAILURE() << where << ": exit 0 with stderr line: " << line.substr(0, 300);
                        clean = false;
                    }
            } else {
                ++refused;
                if (err.size() != 1 || err[0].rfind("brume: error: ", 0) != 0 || o.stderr_text.size() > kMaxErrorBytes) {
                    ADD_FAILURE() << where << ": exit " << o.status << " with " << err.size() << " stderr lines, "
                                  << o.stderr_text.size() << " bytes: " << o.stderr_text.substr(0, 300);
                    clean = false;
                }
                if (read(out_dir / "out.exr") != kSentinel) {
                    ADD_FAILURE() << where << ": exit " << o.status << ", and the existing out.exr was changed";
                    clean = false;
                }
            }
            const std::vector<std::string> left = listing(out_dir);
            if (left != std::vector<std::string>{"out.exr"}) {
                std::string names;
                for (const std::string& n : left) names += " " + n;
                ADD_FAILURE() << where << ": the output folder holds" << names;
                clean = false;
            }
            if (clean) fs::remove_all(dir);  // a failing case's input stays for the reader
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%d runs of %zu files: %d rendered, %d refused, %.1f s\n", cases, files.size(), rendered, refused, seconds);
    EXPECT_GT(refused, cases / 4);   // the mutations do reach the checks
    EXPECT_GT(rendered, cases / 20); // and some still render, so the writers are exercised too
    EXPECT_LT(seconds, 60.0);        // the bound for the fuzz run; a slower machine shows it here
}

}  // namespace
}  // namespace brume
