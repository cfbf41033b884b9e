#include "render/methods/auto_method.h"

#include "sim/sphere_overlap.h"

#include <chrono>

namespace brume {

AutoMethod::AutoMethod(vk::Device& device)
    : ppll_(device), power_sorted_(device, SortedCompositor::Billboard::Spherical, SortedCompositor::SortKey::PowerDistance) {}

Image AutoMethod::render(const Scene& scene, FrameStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    const bool intersecting = find_intersecting_spheres(scene.spheres).has_value();
    const double decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    last_choice_ = intersecting ? "ppll" : "power-sorted";
    Image image = intersecting ? ppll_.render(scene, stats, false) : power_sorted_.render(scene, stats);
    if (stats) {
        // The decision is CPU work the frame cannot skip: it counts in the frame's time.
        stats->passes.insert(stats->passes.begin(), {"decide (cpu): " + last_choice_, decide_ms});
        stats->total_ms += decide_ms;
    }
    return image;
}

}  // namespace brume
