#include "sim/layers_scene.h"

#include <stdexcept>

namespace brume {

Scene make_layers_scene(int layers, int width, int height) {
    if (layers < 2 || layers % 2 != 0) throw std::invalid_argument("layer count must be even and at least 2");
    Scene scene;
    scene.source = "layers benchmark (" + std::to_string(layers) + " layers)";
    scene.camera.position = {0.0, 0.0, 0.0};
    scene.camera.look_at = {0.0, 0.0, -1.0};
    scene.camera.up = {0.0, 1.0, 0.0};
    scene.camera.fov_y_deg = 60.0;
    scene.camera.width = width;
    scene.camera.height = height;
    scene.render.min_transmittance = 0.0;
    // A corner ray of a 60-degree, 16:9-or-narrower view is at most ~50 degrees off axis; a sphere
    // at distance D with radius 0.9 D subtends 64 degrees, so every ray enters and leaves it.
    for (int k = 0; k < layers / 2; ++k) {
        const double distance = 10.0 + 0.75 * k;
        Sphere s;
        s.center = {0.03 * k, -0.02 * k, -distance};
        s.radius = 0.9 * distance;
        s.extinction = 0.01;
        s.albedo = {0.9 - 0.02 * k, 0.85, 0.8 + 0.01 * k};
        scene.spheres.push_back(s);
    }
    return scene;
}

}  // namespace brume
