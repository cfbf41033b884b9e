// The method catalogue: one entry per method, carrying its factory, the command-line options it
// honours and the settings `brume bench` sweeps. Options, benchmarks, `brume methods` and the
// parameterised tests all read this table, so a new method is added here once (docs/architecture.md).
#pragma once

#include "render/methods/method.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brume {

namespace vk {
class Device;
}

// The command-line options that reach methods; each entry says which it honours.
struct MethodOptions {
    std::uint64_t max_pool_bytes = 0;      // --max-memory: budget of per-pixel lists; 0: half the device heap
    std::uint64_t initial_pool_nodes = 0;  // --pool-nodes: first list-pool size; 0: estimated from the scene
    int threads = 0;                       // --threads: the CPU tracers' threads; 0: all (every method
                                           // runs within it: the command caps usable_cpus too)
};

enum MethodOptionBits : unsigned {
    kHonoursMaxMemory = 1u << 0,  // --max-memory: the bound on a method's list memory (ppll's pool, tiles' lists)
    kHonoursPoolNodes = 1u << 2,  // --pool-nodes (render's only): the first size of a node pool (ppll, and auto's)
};

struct MethodEntry {
    using Factory = std::unique_ptr<Method> (*)(vk::Device* device, const std::string& setting,
                                                const MethodOptions& options);
    std::string name;             // "kbuf"
    std::string setting;          // what the part after ':' means, empty if none
    std::string default_setting;  // the setting an empty one means (for display)
    std::string summary;          // one line
    bool needs_device = true;     // false: runs on the CPU
    bool exact = false;           // matches the reference to float precision on every scene it accepts
    bool list_stats = false;      // fills FrameStats' per-pixel list figures
    unsigned options = 0;         // MethodOptionBits
    // Settings `brume bench` renders besides the default, to show a trade-off.
    std::vector<std::string> bench_settings;
    Factory make = nullptr;
    // Parses a setting as the factory will, without a device, throwing std::invalid_argument where it
    // would; null for a method that takes none. So a bad `kbuf:0` is refused as a command-line error
    // before the (slow) device is made, not by the factory after it.
    using SettingCheck = void (*)(const std::string& setting);
    SettingCheck check_setting = nullptr;
};

// Every method, in charting order.
const std::vector<MethodEntry>& method_catalogue();
// The entry of "kbuf" or "kbuf:8"; throws std::invalid_argument listing the known names.
const MethodEntry& find_method(const std::string& spec);
// "ppll", "reference", "kbuf:8", ... Throws std::invalid_argument naming the method or setting and
// listing the known ones. `device` may be null only for methods that need no GPU.
std::unique_ptr<Method> make_method(vk::Device* device, const std::string& spec, const MethodOptions& options = {});
// Throws std::invalid_argument when `spec` names no method, gives a setting to a method that takes
// none, or a setting its method refuses: everything make_method would refuse but the device.
void check_method_spec(const std::string& spec);
// Throws std::invalid_argument when an option was given (`given`, MethodOptionBits) that the method
// of `spec` does not honour, naming the option and the methods that do.
void check_method_options(const std::string& spec, unsigned given);
// A `--methods` list split into specs: on commas, but a token that names no method completes the spec
// before it when that one's setting may hold a comma ("stochastic:8,depth,ppll" is two specs, as
// `brume methods` writes stochastic's setting S[,plain|,depth]). Empty items are dropped. The specs
// are not checked: check_method_spec does that.
std::vector<std::string> split_method_list(const std::string& text);
// The lines `brume methods` prints: NAME[:SETTING] in a column as wide as the widest, then the summary,
// the default setting, [exact] and the options the method honours.
std::vector<std::string> method_listing();
// What `brume bench` renders by default: every entry at its default setting, then its sweeps.
std::vector<std::string> bench_method_specs();

}  // namespace brume
