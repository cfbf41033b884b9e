#include "app/preview_reference.h"

#include "render/image_compare.h"
#include "render/reference.h"
#include "sim/usable_cpus.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace brume::app {

ReferenceCheck::~ReferenceCheck() {
    if (job_.valid()) job_.wait();  // the worker reads the scene it was given: let it finish
}

void ReferenceCheck::reduced_size(int width, int height, int& out_width, int& out_height) {
    const double scale = std::min(1.0, double(kMaxSide) / std::max(width, height));
    out_width = std::max(1, int(std::lround(width * scale)));
    out_height = std::max(1, int(std::lround(height * scale)));
}

bool ReferenceCheck::start(const Scene& scene, Image method_image, int frame, const std::string& method) {
    if (job_.valid()) return false;
    error_.clear();
    pixels_done_.store(0, std::memory_order_relaxed);
    pixels_total_ = std::uint64_t(scene.camera.width) * std::uint64_t(scene.camera.height);
    // The job counts into pixels_done_, which outlives it (the destructor waits for the job).
    job_ = std::async(std::launch::async, [scene, image = std::move(method_image), frame, method,
                                           done = &pixels_done_] {
        const auto t0 = std::chrono::steady_clock::now();
        ReferenceOptions options;
        // One core stays with the window (and lavapipe) so that it keeps drawing.
        options.threads = int(std::max(2u, usable_cpus()) - 1);
        options.pixels_done = done;
        // A scene shaded by the per-sphere shadow technique (the shipped presets) is compared with the
        // reference's per-sphere mode, the model the methods compute (docs/accuracy.md).
        if (scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::PerSphere)
            options.shadows = ReferenceShadows::PerSphere;
        const Image reference = render_reference(scene, options);
        ReferenceError r;
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const ImageDiff diff = compare_images(image, reference, 0.0);
        const double peak = diff.peak > 0.0 ? diff.peak : 1.0;
        r.frame = frame;
        r.method = method;
        r.width = scene.camera.width;
        r.height = scene.camera.height;
        r.max_of_peak = diff.max_abs / peak;
        r.rmse_of_peak = diff.rmse / peak;
        r.psnr_db = diff.psnr_db;
        return r;
    });
    return true;
}

void ReferenceCheck::poll() {
    if (!job_.valid() || job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    try {
        last_ = job_.get();
    } catch (const std::exception& e) {
        error_ = e.what();
        job_ = {};
    }
}

}  // namespace brume::app
