// Small parsing and output helpers shared by the subcommands.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace brume {

struct Preset;
struct VolumeReport;
}

namespace brume {
struct Image;
struct Scene;
}

namespace brume::app {

// A wrong option value found after parsing (--frames 5-2, --size abc, -o X --png X): a bad command
// line like CLI11's own errors, so main exits with 2 (docs/decisions.md, "Errors"). It is an
// invalid_argument, so code that catches those still does.
class UsageError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// The method checks of the registry (an unknown name, a bad setting, an option the method ignores) as
// UsageError.
void check_method_usage(const std::string& method, unsigned given_options);
// --device and --validate choose and check a Vulkan device: refused (UsageError) for a method that runs on
// the CPU alone (reference), which would ignore them, as every option a method would ignore is.
void check_device_options(const std::string& method, const std::string& device, bool validate);

// "512M", "2G", "1.5GiB", "1000000" -> bytes. Throws std::invalid_argument naming the text.
std::uint64_t parse_bytes(const std::string& text);
// "800x600" -> {800, 600}. Throws std::invalid_argument.
void parse_size(const std::string& text, int& width, int& height);
// A whole decimal number of `text` (optional '-' then digits, nothing else), or nullopt when it is
// not one or does not fit in 64 bits: "4294967328" stays 4294967328, never wraps to 32.
std::optional<long long> parse_whole_number(std::string_view text);
// Refuses an output path whose extension names another format than the one `option` writes
// (`-o out.png` would otherwise be OpenEXR bytes in a .png file). `extension` is ".exr", ".png",
// ".vdb" or ".toml"; a path without an extension (/dev/null, a pipe) is taken as it is.
void check_output_format(const std::string& option, const std::string& path, const std::string& extension);
// A result that may be wrong is never written: throws std::runtime_error naming how many pixels of
// `what` are NaN or infinite and where the first is.
void refuse_non_finite(const Image& image, const std::string& what);
// A CLI11 check for file options: "" is refused ("-o ''" once wrote brume.exr and brume.png in the
// working directory, as if no -o had been given). Returns the message, or "" when `text` is fine.
std::string refuse_empty_path(const std::string& text);
// Checks for CLI11 options, as refuse_empty_path: "" when `text` is fine, else what is wrong with it. CLI11's
// own PositiveNumber and NonNegativeNumber print their upper bound, the largest double, in full (309 digits).
std::string refuse_non_positive(const std::string& text);    // a finite number > 0
std::string refuse_non_frame_number(const std::string& text); // a whole number from 0 to 2^31 - 1
std::string refuse_outside_unit_interval(const std::string& text);   // a number in [0, 1] (NaN is not: CLI::Range let it by)
std::string refuse_outside_half_open_unit(const std::string& text);  // a number in (0, 1]
// "2,4,8" or "2-16:2" -> numbers. Throws std::invalid_argument.
std::vector<int> parse_int_list(const std::string& text);

// "a,b,,c" -> {"a", "b", "c"}: the comma-separated items, empty ones dropped.
std::vector<std::string> split_commas(const std::string& text);

double median(std::vector<double> values);

// A bench's warm-up: calls `frame` once (pipelines compile, caches fill), then again until `min_ms`
// of wall clock have passed, at most `max_frames` calls in all. A GPU left idle while the CPU
// reference ran lowers its clocks, and one short frame does not raise them again: on an H200 the
// tiles resolve read 18 ms after the reference's seconds and 3 ms after other GPU work
// (docs/performance.md, "On an NVIDIA H200"). min_ms = 0: the one call.
void warm_up(const std::function<void()>& frame, double min_ms, int max_frames = 1000);
// The warm-up time a bench gives a method on `device_type` (VkPhysicalDeviceType): none on a CPU device
// (lavapipe has no clocks to raise, and the benches there are long already), 300 ms on any other.
double warm_up_ms(int device_type);

// "1 sphere", "2 spheres", "0 spheres": a count with its noun in the right number.
std::string count_of(std::size_t n, const char* singular, const char* plural);

// One line on what converting a [[vdb]] volume did: spheres, voxels, measured error, time.
void print_volume_report(const VolumeReport& report);

// A note where the scene has more outsized spheres (render/outsized_spheres.h) than the accurate shadow
// technique takes whole: the rest blur its map past its stated error. Nothing otherwise; false then.
bool note_outsized_spheres(const Scene& scene);

// --threads N (N > 0) for the whole run: every parallel loop holds to N CPUs (cap_usable_cpus,
// sim/usable_cpus.h), and lavapipe's rasterizer, which starts a thread for every CPU, to N threads
// (LP_NUM_THREADS, unless the environment sets it). Call before a device is made.
void hold_run_to_threads(int threads);

// Refuses a preset read from a scene file (Preset::still) where frames are asked for (play, render
// --frame): it would be the same image every frame. `asked` says what asked for frames ("play plays a
// preset's frames").
void refuse_still_scene(const Preset& preset, const std::string& asked);

// A JSON string literal (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& text);

}  // namespace brume::app
