// How far a sphere cloud's optical depth is from its grid's, measured over the pixel rays of a camera:
// the grid's optical depth exactly (the trilinear field is a cubic between voxel planes, which Simpson's
// rule integrates exactly) against the spheres' sum of extinction * chord. This is the error that
// grid_to_spheres' tolerance aims at but does not bound: see sphere_cloud.h.
#pragma once

#include "sim/scene.h"
#include "sim/density_grid.h"

#include <vector>

namespace brume {

struct OpticalDepthError {
    // Over the rays where either model has optical depth, with d = spheres - grid per ray:
    double relative_rms = 0.0;  // sqrt(sum d^2 / sum grid^2)
    double relative_max = 0.0;  // max |d| / max grid
    double bias = 0.0;          // sum d / sum grid: a systematic excess (+) or deficit (-)
    double max_grid_depth = 0.0;
    int rays = 0;  // rays that meet either model
};

// Optical depth of the grid (density * extinction_scale) along the ray origin + t * unit_dir, t >= 0.
double grid_optical_depth(const DensityGrid& grid, double extinction_scale, const glm::dvec3& origin,
                          const glm::dvec3& unit_dir);

// Per pixel (row-major, top row first), the optical depth of the spheres along the camera's pixel-centre
// rays (sim/camera_rays.h), along the whole ray (t >= 0).
std::vector<double> sphere_optical_depths(const std::vector<Sphere>& spheres, const Camera& camera);

OpticalDepthError measure_optical_depth_error(const DensityGrid& grid, double extinction_scale,
                                              const std::vector<Sphere>& spheres, const Camera& camera);

}  // namespace brume
