// Scene builders the test suites share: a camera looking at the origin from +z, and spheres.
#pragma once

#include "sim/scene.h"

namespace brume::testing {

// A w x h view of the origin from (0, 0, 5), integrating everything (min_transmittance 0).
inline Scene small_scene(int w, int h) {
    Scene s;
    s.source = "test";
    s.camera.position = {0.0, 0.0, 5.0};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.width = w;
    s.camera.height = h;
    s.render.min_transmittance = 0.0;
    return s;
}

inline Sphere sphere(glm::dvec3 c, double r, double tau, glm::dvec3 albedo = {0.9, 0.8, 0.7}) {
    Sphere s;
    s.center = c;
    s.radius = r;
    s.extinction = tau;
    s.albedo = albedo;
    return s;
}

}  // namespace brume::testing
