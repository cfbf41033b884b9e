// Where the camera is at time t of a preset: the scene's fixed camera, keyframes joined by cubic
// Hermite segments (C1 in time), or an orbit. Only position and look_at move; up, field of view and resolution stay the scene's.
#pragma once

#include "sim/preset.h"

namespace brume {

Camera camera_at(const Preset& preset, double time_seconds);

}  // namespace brume
