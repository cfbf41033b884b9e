// The "scale" benchmark scene (`brume bench scale`): a random smoke cloud of N spheres filling a ball,
// seen from outside at a fixed distance. Sphere radius shrinks as N^-1/3 and extinction grows as
// N^1/3, so the cloud's volume fraction, its overlap depth and its optical depth stay the same while
// the per-pixel lists grow as N^1/3: the scene isolates how a method's cost follows list length.
#pragma once

#include "sim/scene.h"

#include <cstddef>
#include <cstdint>

namespace brume {

// Deterministic for a given (spheres, seed). At 1,000 spheres the radius is 0.2 of the cloud's
// (unit) radius; the optical depth through the centre is about 1.5, so early termination does not
// hide the list cost (min_transmittance is 0).
Scene make_smoke_cloud_scene(std::size_t spheres, int width, int height, std::uint64_t seed = 1);

}  // namespace brume
