#include "sim/camera_path.h"

#include "sim/camera_rays.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace brume {
namespace {

// Tangent (units per second) at key i: central difference over its neighbours' times, one-sided at
// the ends. Measured per second, not per segment, so the camera's velocity is continuous across
// keys even when they are unevenly spaced (a uniform Catmull-Rom would jerk at every key).
glm::dvec3 tangent(const std::vector<CameraKey>& k, std::size_t i, glm::dvec3 CameraKey::*field) {
    const std::size_t lo = i == 0 ? 0 : i - 1, hi = std::min(i + 1, k.size() - 1);
    return (k[hi].*field - k[lo].*field) / (k[hi].time - k[lo].time);
}

// Cubic Hermite between keys i and i + 1 at time t.
glm::dvec3 hermite(const std::vector<CameraKey>& k, std::size_t i, double t, glm::dvec3 CameraKey::*field) {
    const double h = k[i + 1].time - k[i].time, u = (t - k[i].time) / h;
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * (k[i].*field) + (u3 - 2 * u2 + u) * h * tangent(k, i, field) +
           (-2 * u3 + 3 * u2) * (k[i + 1].*field) + (u3 - u2) * h * tangent(k, i + 1, field);
}

}  // namespace

Camera camera_on_path(const Preset& preset, double t) {
    Camera camera = preset.scene.camera;
    const CameraPath& path = preset.camera_path;
    switch (path.kind) {
    case CameraPath::Kind::Static:
        break;
    case CameraPath::Kind::Keyframes: {
        const auto& k = path.keys;
        if (k.empty()) break;
        if (k.size() == 1 || t <= k.front().time) {
            camera.position = k.front().position;
            camera.look_at = k.front().look_at;
            break;
        }
        if (t >= k.back().time) {
            camera.position = k.back().position;
            camera.look_at = k.back().look_at;
            break;
        }
        std::size_t i = 0;  // the segment [k[i], k[i + 1]] holding t
        while (i + 2 < k.size() && t >= k[i + 1].time) ++i;
        camera.position = hermite(k, i, t, &CameraKey::position);
        camera.look_at = hermite(k, i, t, &CameraKey::look_at);
        break;
    }
    case CameraPath::Kind::Orbit: {
        const double deg = path.orbit_start_deg + path.orbit_deg_per_second * t;
        const double rad = deg * 3.14159265358979323846 / 180.0;
        camera.position = path.orbit_center +
                          glm::dvec3(path.orbit_radius * std::sin(rad), path.orbit_height, path.orbit_radius * std::cos(rad));
        camera.look_at = path.orbit_center;
        break;
    }
    }
    return camera;
}

Camera camera_at(const Preset& preset, double t) {
    const Camera camera = camera_on_path(preset, t);
    if (const std::string why = undefined_view(camera); !why.empty()) {
        std::ostringstream m;
        m.precision(6);
        m << "camera_path: at " << t << " s the camera's view is undefined: " << why << " (position [" << camera.position.x
          << ", " << camera.position.y << ", " << camera.position.z << "], look_at [" << camera.look_at.x << ", "
          << camera.look_at.y << ", " << camera.look_at.z << "]); move a key, or set [camera] up to a direction the view never takes";
        throw CameraPathError(m.str());
    }
    return camera;
}

}  // namespace brume
