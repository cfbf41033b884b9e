#include "render/methods/reference_method.h"

#include "render/reference.h"

#include <chrono>

namespace brume {

Image ReferenceMethod::render(const Scene& scene, FrameStats* stats) {
    ReferenceOptions options;
    options.threads = threads_;
    options.pixels_done = pixels_done_;
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
