#include "render/nearest_bounds.h"

#include "sim/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace brume {

void nearest_event_bounds(const Scene& scene, std::vector<double>& bound, int threads) {
    const glm::dvec3 eye = scene.camera.position;
    const double eye_length = glm::length(eye);
    const std::size_t n = scene.spheres.size();
    bound.resize(n);
    constexpr std::size_t kChunk = 1 << 14;  // three square roots a sphere: a million take 10 ms on one core
    parallel_for((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk, int) {
        for (std::size_t k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k) {
            const Sphere& s = scene.spheres[k];
            const double distance = glm::length(s.center - eye);
            const double margin = 1e-5 * (distance + s.radius + glm::length(s.center) + eye_length);
            bound[k] = distance - s.radius - margin;
        }
    });
}

}  // namespace brume
