// The "layers" benchmark scene of Barta & Kovács' Tables 1-2: every pixel sees exactly `layers` sphere
// surfaces, from layers/2 large concentric-ish spheres that each enclose the whole view frustum
// ahead of the eye (the eye outside them), so both the entry and the exit surface cover the screen.
#pragma once

#include "sim/scene.h"

namespace brume {

// `layers` must be even and >= 2. Extinction is low and min_transmittance 0 so that every layer is
// integrated: the benchmark measures list building and sorting, not early termination.
Scene make_layers_scene(int layers, int width, int height);

}  // namespace brume
