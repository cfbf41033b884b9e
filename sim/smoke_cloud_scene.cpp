#include "sim/smoke_cloud_scene.h"

#include "sim/rng.h"

#include <cmath>
#include <stdexcept>

namespace brume {

Scene make_smoke_cloud_scene(std::size_t spheres, int width, int height, std::uint64_t seed) {
    if (spheres == 0) throw std::invalid_argument("a smoke cloud needs at least one sphere");
    Scene scene;
    scene.source = "smoke cloud (" + std::to_string(spheres) + " spheres, seed " + std::to_string(seed) + ")";
    scene.camera.position = {0.0, 0.3, 3.6};
    scene.camera.look_at = {0.0, 0.0, 0.0};
    scene.camera.up = {0.0, 1.0, 0.0};
    scene.camera.fov_y_deg = 40.0;
    scene.camera.width = width;
    scene.camera.height = height;
    scene.render.min_transmittance = 0.0;

    const double scale = std::cbrt(1000.0 / double(spheres));  // 1 at 1,000 spheres
    const double radius = 0.2 * scale;
    // Mean optical depth through the centre of a ball of unit radius filled with N spheres of
    // radius r and extinction tau: N (4/3 pi r^3) tau * (2 / (4/3 pi)) = 2 N r^3 tau. Held at 1.5.
    const double extinction = 1.5 / (2.0 * double(spheres) * radius * radius * radius);
    const std::uint64_t key = rng::hash(seed, 0x736d6f6b65ull /* "smoke" */);
    scene.spheres.reserve(spheres);
    for (std::size_t k = 0; k < spheres; ++k) {
        // Uniform in the ball: a uniform direction and a radius distributed as u^(1/3).
        const glm::dvec3 dir = rng::sphere_direction(rng::uniform(key, 4 * k), rng::uniform(key, 4 * k + 1));
        const double rho = std::cbrt(rng::uniform(key, 4 * k + 2));
        Sphere s;
        s.center = dir * rho;
        s.radius = radius;
        s.extinction = extinction;
        const double tint = rng::uniform(key, 4 * k + 3);
        s.albedo = {0.78 + 0.1 * tint, 0.8 + 0.05 * tint, 0.84};
        scene.spheres.push_back(s);
    }
    return scene;
}

}  // namespace brume
