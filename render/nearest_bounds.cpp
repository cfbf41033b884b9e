#include "render/nearest_bounds.h"

#include <glm/geometric.hpp>

namespace brume {

void nearest_event_bounds(const Scene& scene, std::vector<double>& bound) {
    const glm::dvec3 eye = scene.camera.position;
    bound.resize(scene.spheres.size());
    for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
        const Sphere& s = scene.spheres[k];
        const double distance = glm::length(s.center - eye);
        const double margin = 1e-5 * (distance + s.radius + glm::length(s.center) + glm::length(eye));
        bound[k] = distance - s.radius - margin;
    }
}

}  // namespace brume
