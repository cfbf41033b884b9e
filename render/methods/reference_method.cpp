#include "render/methods/reference_method.h"

#include "render/reference.h"

#include <chrono>

namespace brume {

Image ReferenceMethod::render(const Scene& scene, FrameStats* stats) {
    ReferenceOptions options;
    options.threads = threads_;
    options.pixels_done = pixels_done_;
    // A scene that asks for the per-sphere technique (`--shadows per-sphere`, crossing, pop) gets the
    // reference's per-sphere mode: that approximation computed in double, what the methods that shade by
    // it are measured against (docs/accuracy.md). `accurate` asks for the model itself, exactly.
    if (scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::PerSphere)
        options.shadows = ReferenceShadows::PerSphere;
    const auto start = std::chrono::steady_clock::now();
    Image image = render_reference(scene, options);
    if (stats) {
        *stats = FrameStats{};
        stats->total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        stats->passes = {{"reference (CPU wall clock)", stats->total_ms}};
    }
    return image;
}

}  // namespace brume
