#include "app/preview_camera.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace brume::app {
namespace {

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

// Rodrigues' rotation of v by `angle` radians about the unit axis k (right-handed).
glm::dvec3 rotate(const glm::dvec3& v, double angle, const glm::dvec3& k) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0 - c));
}

}  // namespace

Camera orbit_camera(const Camera& camera, double deg_x, double deg_y) {
    Camera out = camera;
    const glm::dvec3 k = glm::normalize(camera.up);
    glm::dvec3 d = rotate(camera.position - camera.look_at, radians(deg_x), k);
    const double elevation = std::asin(std::clamp(glm::dot(d, k) / glm::length(d), -1.0, 1.0));
    const double limit = radians(89.0);
    const double wanted = std::clamp(elevation + radians(deg_y), -limit, limit);
    d = rotate(d, wanted - elevation, glm::normalize(glm::cross(d, k)));
    out.position = camera.look_at + d;
    return out;
}

Camera pan_camera(const Camera& camera, double right, double up) {
    Camera out = camera;
    const glm::dvec3 forward = camera.look_at - camera.position;
    const glm::dvec3 r = glm::normalize(glm::cross(forward, camera.up));
    const glm::dvec3 u = glm::normalize(glm::cross(r, forward));
    const double view_height = 2.0 * glm::length(forward) * std::tan(radians(camera.fov_y_deg) / 2.0);
    const glm::dvec3 move = (r * right + u * up) * view_height;
    out.position += move;
    out.look_at += move;
    return out;
}

Camera zoom_camera(const Camera& camera, double factor) {
    Camera out = camera;
    const glm::dvec3 d = camera.position - camera.look_at;
    const double distance = glm::length(d);
    out.position = camera.look_at + d * (std::max(distance * factor, 1e-3) / distance);
    return out;
}

}  // namespace brume::app
