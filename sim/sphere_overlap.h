// Whether any two spheres of a scene share volume. When none do, sorting spheres by power
// distance |c - eye|^2 - r^2 gives their exact visibility order along every ray from the eye, so a
// sort replaces per-pixel lists (the `auto` method's test, docs/decisions.md).
#pragma once

#include "sim/scene.h"

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace brume {

// A pair (lower index first) of spheres with |c_a - c_b| < r_a + r_b, ignoring spheres with no
// extinction; nullopt when every pair is disjoint or merely touching. Neighbours in scene order are
// tried first (O(n)); then a sweep along x, O(n log n) plus the pairs whose x-extents overlap.
std::optional<std::pair<std::size_t, std::size_t>> find_intersecting_spheres(const std::vector<Sphere>& spheres);

// Indices of `spheres` ordered front to back by power distance from `eye` (ties by index).
std::vector<std::size_t> power_distance_order(const std::vector<Sphere>& spheres, const glm::dvec3& eye);

}  // namespace brume
