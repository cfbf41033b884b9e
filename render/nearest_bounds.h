// The exact GPU resolves take spheres in order of a lower bound of every distance at which a
// sphere's ray events can lie: its nearest possible distance from the eye, less a float margin. A
// later sphere then has no event before the current one's bound, so the resolve may integrate every
// pending event before it (ppll's ordered path, tiles).
#pragma once

#include "sim/scene.h"

#include <vector>

namespace brume {

// bound[k] = |c_k - eye| - r_k - margin. The shaders find the events in float, from float copies
// of c, e and r, and compare them with float(bound): the margin covers that rounding (about 1e-6 of
// these magnitudes) ten times over, so a float event is never before its float bound.
// Over `threads` as parallel_for's (0: every usable CPU).
void nearest_event_bounds(const Scene& scene, std::vector<double>& bound, int threads = 0);

}  // namespace brume
