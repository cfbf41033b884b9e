// The method catalogue and `--method NAME[:SETTING]` parsing.
#include "render/methods/registry.h"

#include "render/methods/auto_method.h"
#include "render/methods/cpu_trace_pass.h"
#include "render/methods/kbuffer.h"
#include "render/methods/peel.h"
#include "render/methods/ppll.h"
#include "render/methods/reference_method.h"
#include "render/methods/screendoor.h"
#include "render/methods/soft.h"
#include "render/methods/sorted.h"
#include "render/methods/stochastic.h"
#include "render/methods/tiles.h"
#include "render/methods/weighted.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace brume {

namespace {

// Factories: the entry's name and setting syntax were checked before they are called.
template <auto MakeFromSetting>
std::unique_ptr<Method> gpu_method(vk::Device* device, const std::string& setting, const MethodOptions&) {
    return MakeFromSetting(*device, setting);
}

PpllOptions ppll_options(const MethodOptions& options) {
    PpllOptions ppll;
    ppll.max_pool_bytes = options.max_pool_bytes;
    ppll.initial_nodes = options.initial_pool_nodes;
    return ppll;
}

std::unique_ptr<Method> make_ppll(vk::Device* device, const std::string&, const MethodOptions& options) {
    return std::make_unique<PpllMethod>(*device, ppll_options(options));
}

std::unique_ptr<Method> make_ppll_general(vk::Device* device, const std::string&, const MethodOptions& options) {
    PpllOptions ppll = ppll_options(options);
    ppll.ordered_path = false;
    return std::make_unique<PpllMethod>(*device, ppll);
}

std::unique_ptr<Method> make_tiles(vk::Device* device, const std::string&, const MethodOptions& options) {
    TilesOptions tiles;
    tiles.max_bytes = options.max_pool_bytes;
    return std::make_unique<TilesMethod>(*device, tiles);
}

std::unique_ptr<Method> make_auto(vk::Device* device, const std::string&, const MethodOptions& options) {
    AutoOptions a;
    a.ppll = ppll_options(options);
    a.tiles.max_bytes = options.max_pool_bytes;
    a.threads = options.threads;
    return std::make_unique<AutoMethod>(*device, a);
}

std::unique_ptr<Method> make_trace(vk::Device* device, const std::string&, const MethodOptions& options) {
    return std::make_unique<CpuTracePass>(*device, CpuTracer::Fast, options.threads);
}

std::unique_ptr<Method> make_reference(vk::Device*, const std::string&, const MethodOptions& options) {
    return std::make_unique<ReferenceMethod>(options.threads);
}

// The setting checks (MethodEntry::check_setting): each method's own parser, its result dropped.
void check_kbuf(const std::string& setting) { (void)parse_kbuf_setting(setting); }
void check_peel(const std::string& setting) { (void)parse_peel_setting(setting); }
void check_stochastic(const std::string& setting) { (void)parse_stochastic_setting(setting); }
void check_screendoor(const std::string& setting) { (void)parse_screendoor_setting(setting); }

std::string option_names(unsigned bits) {
    std::string out;
    // Only the options given: play has no --pool-nodes to name.
    if (bits & kHonoursMaxMemory) out += "--max-memory";
    if (bits & kHonoursPoolNodes) out += std::string(out.empty() ? "" : ", ") + "--pool-nodes";
    return out;
}

}  // namespace

const std::vector<MethodEntry>& method_catalogue() {
    static const std::vector<MethodEntry> catalogue = {
        {"ppll", "", "",
         "per-pixel linked lists, exact intersecting media (GPU); spheres drawn far to near, each list merged in one walk",
         true, true, true, kHonoursMaxMemory | kHonoursPoolNodes, {}, &make_ppll},
        {"ppll-general", "", "",
         "ppll with every pixel resolved by repeated walks of its list, O(n^2): the resolve before the ordered one",
         true, true, true, kHonoursMaxMemory | kHonoursPoolNodes, {}, &make_ppll_general},
        {"tiles", "", "",
         "exact intersecting media in compute, no per-pixel lists: spheres binned to 8x8 tiles near to far, each "
         "pixel merging its tile's events in one pass",
         true, true, true, kHonoursMaxMemory, {}, &make_tiles},
        {"trace", "", "",
         "CPU ray tracer in float: spheres binned to 8x8 tiles near to far, each ray's events merged in a heap "
         "in bound order, stopping once opaque; the fastest exact path on a CPU device",
         true, true, false, 0, {}, &make_trace},
        {"reference", "", "", "CPU ray tracer, double precision, same model (ground truth)", false, true, false, 0,
         {}, &make_reference},
        {"auto", "", "",
         "per frame the cheapest exact path: trace on a CPU device; on a GPU power-distance sorted spheres when none "
         "intersect (and the shadows are not accurate), else the fastest of tiles, ppll and trace as measured",
         true, true, false, kHonoursMaxMemory | kHonoursPoolNodes, {}, &make_auto},
        {"sorted", "", "",
         "painter's algorithm: planar billboards sorted back to front by centre (insertion sort reusing last "
         "frame's order); pops when order flips",
         true, false, false, 0, {}, &gpu_method<make_sorted_method>},
        {"soft", "", "",
         "sorted spherical billboards (soft particles): chord clipped by eye and geometry; wrong where spheres "
         "intersect",
         true, false, false, 0, {}, &gpu_method<make_soft_method>},
        {"wsum", "", "", "weighted sum (Meshkin): unsorted additive blend, one geometry pass", true, false, false, 0,
         {}, &gpu_method<make_wsum_method>},
        {"wavg", "", "", "weighted average (Bavoil & Myers): unsorted, one geometry pass", true, false, false, 0, {},
         &gpu_method<make_wavg_method>},
        {"wboit", "", "", "weighted blended OIT (McGuire & Bavoil 2013, eq. 9 depth weight)", true, false, false, 0,
         {}, &gpu_method<make_wboit_method>},
        {"kbuf", "k", "8", "k nearest spheres per pixel (FreePipe / k-buffer, k = 1..32), tail as one averaged layer",
         true, false, false, 0, {"4", "16"}, &gpu_method<make_kbuf_method>, &check_kbuf},
        {"peel", "[dual:]N", "8",
         "depth peeling: N geometry passes front to back (1..64), or peel:dual:N peeling a front and a back layer "
         "per pass; layers beyond as one slab",
         true, false, false, 0, {"4", "16", "dual:8"}, &gpu_method<make_peel_method>, &check_peel},
        {"stochastic", "S[,plain|,depth]", "8",
         "stochastic transparency with S samples per pixel (power of two, 1..64), alpha-corrected unless ',plain'; "
         "',depth': depth-based visibility (Enderton et al.)",
         true, false, false, 0, {"4", "16", "8,depth"}, &gpu_method<make_stochastic_method>, &check_stochastic},
        {"screendoor", "S", "4", "object-space screen-door transparency with S x S supersampling (S = 1..8)", true,
         false, false, 0, {"2"}, &gpu_method<make_screendoor_method>, &check_screendoor},
    };
    return catalogue;
}

const MethodEntry& find_method(const std::string& spec) {
    const std::string name = spec.substr(0, spec.find(':'));
    for (const MethodEntry& m : method_catalogue())
        if (m.name == name) return m;
    std::string known;
    for (const MethodEntry& m : method_catalogue()) known += (known.empty() ? "" : ", ") + m.name;
    throw std::invalid_argument("unknown method '" + name + "'; known: " + known);
}

namespace {

std::string setting_of(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    return colon == std::string::npos ? "" : spec.substr(colon + 1);
}

}  // namespace

void check_method_spec(const std::string& spec) {
    const MethodEntry& entry = find_method(spec);
    const std::string setting = setting_of(spec);
    if (!setting.empty() && entry.setting.empty())
        throw std::invalid_argument("method '" + entry.name + "' takes no setting (got ':" + setting + "')");
    // "kbuf:" rendered with the default and was named "kbuf:" in the stats: a ':' with nothing after it
    // is a setting left half written (a variable that was empty), not a request for the default.
    if (setting.empty() && spec.find(':') != std::string::npos)
        throw std::invalid_argument(entry.setting.empty()
                                        ? "method '" + entry.name + "' takes no setting (got ':')"
                                        : "method '" + entry.name + "': an empty setting after ':' (" + entry.name + ":" +
                                              entry.setting + "; leave ':' out for the default, " +
                                              entry.default_setting + ")");
    if (entry.check_setting) entry.check_setting(setting);
}

std::unique_ptr<Method> make_method(vk::Device* device, const std::string& spec, const MethodOptions& options) {
    check_method_spec(spec);
    const MethodEntry& entry = find_method(spec);
    if (entry.needs_device && !device) throw std::invalid_argument("method '" + entry.name + "' needs a Vulkan device");
    return entry.make(device, setting_of(spec), options);
}

void check_method_options(const std::string& spec, unsigned given) {
    const MethodEntry& entry = find_method(spec);
    const auto honoured = [](const MethodEntry& m) { return m.options; };
    const unsigned ignored = given & ~honoured(entry);
    if (!ignored) return;
    std::string honouring;
    for (const MethodEntry& m : method_catalogue())
        if (honoured(m) & ignored) honouring += (honouring.empty() ? "" : ", ") + m.name;
    throw std::invalid_argument(option_names(ignored) + " applies to " + honouring + ", not to method '" +
                                entry.name + "'");
}

std::vector<std::string> split_method_list(const std::string& text) {
    std::vector<std::string> specs;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string token = text.substr(start, comma - start);
        start = comma + 1;
        if (token.empty()) continue;  // "a,,b" and a trailing comma name nothing more
        // "stochastic:8,depth" is one spec whose setting holds a comma: a token that names no method
        // completes the spec before it when that spec's method takes such a setting. Anything else
        // stays a spec of its own, so "ppll,depth" is refused as an unknown method 'depth'.
        if (!specs.empty() && specs.back().find(':') != std::string::npos) {
            const std::string name = token.substr(0, token.find(':'));
            const bool is_method = std::any_of(method_catalogue().begin(), method_catalogue().end(),
                                               [&](const MethodEntry& m) { return m.name == name; });
            const std::string previous = specs.back().substr(0, specs.back().find(':'));
            const auto entry = std::find_if(method_catalogue().begin(), method_catalogue().end(),
                                            [&](const MethodEntry& m) { return m.name == previous; });
            if (!is_method && entry != method_catalogue().end() && entry->setting.find(',') != std::string::npos) {
                specs.back() += "," + token;
                continue;
            }
        }
        specs.push_back(token);
    }
    return specs;
}

std::vector<std::string> method_listing() {
    std::vector<std::pair<std::string, std::string>> rows;  // NAME[:SETTING], summary and notes
    std::size_t width = 0;
    for (const MethodEntry& m : method_catalogue()) {
        std::string name = m.name + (m.setting.empty() ? "" : ":" + m.setting);
        std::string notes = m.summary;
        if (!m.default_setting.empty()) notes += " (default " + m.default_setting + ")";
        if (m.exact) notes += " [exact]";
        if (m.options & kHonoursMaxMemory) notes += " [--max-memory]";
        if (m.options & kHonoursPoolNodes) notes += " [--pool-nodes]";
        width = std::max(width, name.size());
        rows.emplace_back(std::move(name), std::move(notes));
    }
    // One column for the names, as wide as the widest: "stochastic:S[,plain|,depth]" ran into its summary.
    std::vector<std::string> lines;
    for (const auto& [name, notes] : rows) lines.push_back(name + std::string(width + 2 - name.size(), ' ') + notes);
    return lines;
}

std::vector<std::string> bench_method_specs() {
    std::vector<std::string> specs;
    for (const MethodEntry& m : method_catalogue()) {
        if (m.name == "reference") continue;  // every figure is measured against it
        specs.push_back(m.name);
        for (const std::string& s : m.bench_settings) specs.push_back(m.name + ":" + s);
    }
    return specs;
}

}  // namespace brume
