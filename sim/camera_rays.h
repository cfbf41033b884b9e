// The one definition of the pixel-centre ray, shared by the CPU reference and the GPU uniforms,
// so both sample exactly the same rays (docs/accuracy.md).
#pragma once

#include "sim/scene.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace brume {

// Whether a view direction leaves the camera a defined roll: the sine of its angle with up above 1e-9
// (below, cross(forward, up) is ill-conditioned). Both must be non-zero and finite. The one statement of
// the rule: the scene and preset readers and undefined_view all ask it.
inline bool view_has_roll(const glm::dvec3& view, const glm::dvec3& up) {
    return glm::length(glm::cross(glm::normalize(view), glm::normalize(up))) > 1e-9;
}

// Why a camera's view is undefined, or "" when it is defined: make_camera_rays normalises
// look_at - position and cross(forward, up), so the eye must not sit on look_at nor look along up.
// The scene and preset readers refuse such a camera in a file; a moving camera can still pass
// through one between its keys (a fly-over straight above what it looks at), which its callers
// (sim/camera_path.h camera_at) refuse by time.
inline std::string undefined_view(const Camera& c) {
    const glm::dvec3 view = c.look_at - c.position;
    const double view_length = glm::length(view), up_length = glm::length(c.up);
    if (!(view_length > 0.0) || !std::isfinite(view_length)) return "the eye is on look_at (no view direction)";
    if (!(up_length > 0.0) || !std::isfinite(up_length)) return "camera.up is zero";
    if (!view_has_roll(view, c.up))
        return "the view direction (look_at - position) is parallel to camera.up";
    return "";
}

// An orthonormal camera basis with the image-plane half extents folded into right/up:
// dir(i, j) = normalize(forward + ndc_x * right - ndc_y * up), ndc in [-1, 1], y down.
struct CameraRays {
    glm::dvec3 eye;
    glm::dvec3 forward;
    glm::dvec3 right;  // unit right * tan(fov/2) * aspect
    glm::dvec3 up;     // unit up * tan(fov/2)
    int width;
    int height;

    glm::dvec3 direction(double px, double py) const {
        const double ndc_x = 2.0 * px / width - 1.0;
        const double ndc_y = 2.0 * py / height - 1.0;
        return glm::normalize(forward + ndc_x * right - ndc_y * up);
    }
    // Ray through the centre of pixel (i, j).
    glm::dvec3 pixel_direction(int i, int j) const { return direction(i + 0.5, j + 0.5); }
};

// Throws std::invalid_argument where the view is undefined (undefined_view): its rays would be NaN,
// which the tracers would draw as background, a wrong image with no error.
inline CameraRays make_camera_rays(const Camera& c) {
    if (const std::string why = undefined_view(c); !why.empty()) throw std::invalid_argument("the camera's view is undefined: " + why);
    CameraRays r;
    r.eye = c.position;
    r.forward = glm::normalize(c.look_at - c.position);
    const glm::dvec3 right_unit = glm::normalize(glm::cross(r.forward, c.up));
    const glm::dvec3 up_unit = glm::cross(right_unit, r.forward);
    const double tan_half = std::tan(c.fov_y_deg * 0.5 * 3.14159265358979323846 / 180.0);
    const double aspect = double(c.width) / double(c.height);
    r.right = right_unit * (tan_half * aspect);
    r.up = up_unit * tan_half;
    r.width = c.width;
    r.height = c.height;
    return r;
}

}  // namespace brume
