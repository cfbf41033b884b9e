// The method catalogue and `--method NAME[:SETTING]` parsing.
#include "render/methods/method.h"

#include "render/methods/auto_method.h"
#include "render/methods/kbuffer.h"
#include "render/methods/peel.h"
#include "render/methods/ppll.h"
#include "render/methods/reference_method.h"
#include "render/methods/screendoor.h"
#include "render/methods/soft.h"
#include "render/methods/sorted.h"
#include "render/methods/stochastic.h"
#include "render/methods/weighted.h"

#include <stdexcept>

namespace brume {

const std::vector<MethodInfo>& method_catalogue() {
    static const std::vector<MethodInfo> catalogue = {
        {"ppll", "", "", "per-pixel linked lists, exact intersecting media (GPU)"},
        {"reference", "", "", "CPU ray tracer, double precision, same model (ground truth)"},
        {"auto", "", "",
         "per frame the cheapest exact method: power-distance sorted spheres when none intersect, else ppll"},
        {"sorted", "", "",
         "painter's algorithm: planar billboards sorted back to front by centre (insertion sort reusing last "
         "frame's order); pops when order flips"},
        {"soft", "", "",
         "sorted spherical billboards (soft particles): chord clipped by eye and geometry; wrong where spheres "
         "intersect"},
        {"wsum", "", "", "weighted sum (Meshkin): unsorted additive blend, one geometry pass"},
        {"wavg", "", "", "weighted average (Bavoil & Myers): unsorted, one geometry pass"},
        {"wboit", "", "", "weighted blended OIT (McGuire & Bavoil 2013, eq. 9 depth weight)"},
        {"kbuf", "k", "8", "k nearest spheres per pixel (FreePipe / k-buffer, k = 1..32), tail as one averaged layer"},
        {"peel", "N|dual:N", "8",
         "depth peeling: N geometry passes front to back (1..64), or dual:N peeling a front and a back layer per "
         "pass; layers beyond as one slab"},
        {"stochastic", "S[,plain|,depth]", "8",
         "stochastic transparency with S samples per pixel (power of two, 1..64), alpha-corrected unless ',plain'; "
         "',depth': depth-based visibility (Enderton et al.)"},
        {"screendoor", "S", "4", "object-space screen-door transparency with S x S supersampling (S = 1..8)"},
    };
    return catalogue;
}

std::unique_ptr<Method> make_method(vk::Device* device, const std::string& spec) {
    const std::size_t colon = spec.find(':');
    const std::string name = spec.substr(0, colon);
    const std::string setting = colon == std::string::npos ? "" : spec.substr(colon + 1);
    const MethodInfo* info = nullptr;
    for (const MethodInfo& m : method_catalogue())
        if (m.name == name) info = &m;
    if (!info) {
        std::string known;
        for (const MethodInfo& m : method_catalogue()) known += (known.empty() ? "" : ", ") + m.name;
        throw std::invalid_argument("unknown method '" + name + "'; known: " + known);
    }
    if (!setting.empty() && info->setting.empty())
        throw std::invalid_argument("method '" + name + "' takes no setting (got ':" + setting + "')");
    if (name == "reference") return std::make_unique<ReferenceMethod>();
    if (!device) throw std::invalid_argument("method '" + name + "' needs a Vulkan device");
    if (name == "ppll") return std::make_unique<PpllMethod>(*device);
    if (name == "auto") return std::make_unique<AutoMethod>(*device);
    if (name == "sorted") return make_sorted_method(*device, setting);
    if (name == "soft") return make_soft_method(*device, setting);
    if (name == "screendoor") return make_screendoor_method(*device, setting);
    if (name == "wsum") return make_wsum_method(*device, setting);
    if (name == "wavg") return make_wavg_method(*device, setting);
    if (name == "wboit") return make_wboit_method(*device, setting);
    if (name == "kbuf") return make_kbuf_method(*device, setting);
    if (name == "stochastic") return make_stochastic_method(*device, setting);
    if (name == "peel") return make_peel_method(*device, setting);
    throw std::logic_error("method '" + name + "' is catalogued but not constructed");
}

}  // namespace brume
