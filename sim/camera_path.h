// Where the camera is at time t of a preset: the scene's fixed camera, keyframes joined by cubic
// Hermite segments (C1 in time), or an orbit. Only position and look_at move; up, field of view and resolution stay the scene's.
#pragma once

#include "sim/preset.h"

#include <stdexcept>

namespace brume {

// Throws CameraPathError where the path's view is undefined at that time (sim/camera_rays.h
// undefined_view): keys read one by one can still join through a view straight along camera.up, as a
// fly-over does straight above what it looks at, and an orbit about a tilted up can face along it.
Camera camera_at(const Preset& preset, double time_seconds);
// The same camera unchecked, for a caller that reports an undefined view itself (the preview's render
// thread shows make_camera_rays' error for that frame and keeps the window).
Camera camera_on_path(const Preset& preset, double time_seconds);

struct CameraPathError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace brume
