// Placing a density grid in the scene (VolumeTransform, sim/scene.h): one definition for the [[vdb]]
// clouds and the density-seeded emitters, so a cloud and the smoke it seeds line up.
#pragma once

#include "sim/scene.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace brume {

// R: rotate_deg.x about x, then .y about y, then .z about z (R = Rz * Ry * Rx).
glm::dmat3 volume_rotation(const VolumeTransform& t);

// translate + scale * R * p.
glm::dvec3 volume_to_world(const VolumeTransform& t, const glm::dvec3& grid_position);

// The inverse: R^T * (p - translate) / scale.
glm::dvec3 world_to_volume(const VolumeTransform& t, const glm::dvec3& world_position);

// A sphere placed by the transform: centre mapped, radius times scale, extinction (per scene unit) kept.
Sphere volume_to_world(const VolumeTransform& t, const Sphere& grid_sphere);

// The problem with a transform ("scale must be positive and finite (got 0)"), or empty when it is usable.
std::string volume_transform_problem(const VolumeTransform& t);

}  // namespace brume
