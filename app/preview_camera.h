// The preview's camera control: orbit, pan and zoom around the point the camera looks at, starting
// from any camera (the preset's, or where its camera path is now).
//
// Orbit, in closed form (tests/preview_checks.sh recomputes it): with d = position - look_at and
// k = normalize(up), d is turned by DEG_X about k (Rodrigues: d cos a + (k x d) sin a + k (k.d)(1 - cos a);
// positive moves the eye to its right), then by DEG_Y about normalize(cross(d, k)) (positive raises the
// eye), the elevation clamped to +-89 degrees so that up never becomes parallel to d. look_at, up and the
// distance stay.
#pragma once

#include "sim/scene.h"

namespace brume::app {

// `camera` orbited by (deg_x, deg_y) as above.
Camera orbit_camera(const Camera& camera, double deg_x, double deg_y);
// `camera` and its look_at moved by (right, up) fractions of the view's height at the look_at distance.
Camera pan_camera(const Camera& camera, double right, double up);
// `camera` moved toward look_at: the distance is multiplied by `factor` (> 0), never below 1e-3.
Camera zoom_camera(const Camera& camera, double factor);

}  // namespace brume::app
