// How far a sphere cloud's optical depth is from its grid's, measured over the pixel rays of cameras: the
// grid's optical depth exactly (the trilinear field is a cubic between voxel planes, which Simpson's rule
// integrates exactly) against the spheres' sum of extinction * chord. This is the error a sphere cloud's
// tolerance bounds (sim/vdb/sphere_cloud.h).
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"

#include <cstdint>
#include <span>
#include <vector>

namespace brume {

struct OpticalDepthError {
    // Over the rays where either model has optical depth, with d = spheres - grid per ray:
    double relative_rms = 0.0;  // sqrt(sum d^2 / sum grid^2): the figure tolerances bound
    double relative_max = 0.0;  // max |d| / max grid
    double bias = 0.0;          // sum d / sum grid: a systematic excess (+) or deficit (-)
    // sqrt(mean d^2) / max grid: the same differences against one scale for the whole grid, so rays that
    // graze an edge (small grid depth) weigh no more than any other ray
    double absolute_rms = 0.0;
    // mean |exp(-spheres) - exp(-grid)|: the image error of an ambient-lit, unshadowed render of albedo 1
    // over a black background, in units of the ambient radiance (there L = L_ambient * (1 - T) exactly)
    double transmittance_mean = 0.0;
    double max_grid_depth = 0.0;
    long rays = 0;  // rays that meet either model
};

// Optical depth of the grid (density * extinction_scale) along the ray origin + t * unit_dir, t >= 0.
double grid_optical_depth(const DensityGrid& grid, double extinction_scale, const glm::dvec3& origin,
                          const glm::dvec3& unit_dir);

struct CameraRays;

// Which ray a pixel measures along. Centres: through the pixel's centre (sim/camera_rays.h), the rays a fit
// is fitted along. Jittered: through one fixed pseudo-random point of the pixel (a hash of its index), for
// the views that only measure: a regular lattice of rays beats against the voxel lattice, and the Moire
// moves the error with the view's resolution and distance (the one-sphere fit of the fog sphere measured
// 2.22-2.53% from the unseen views at 64-160 pixels through the centres, 2.28-2.35% jittered; docs/vdb.md).
enum class PixelRays { Centres, Jittered };

// The direction of pixel (i, j)'s ray.
glm::dvec3 pixel_ray(const CameraRays& rays, int i, int j, PixelRays sampling);

// Per pixel (row-major, top row first), the optical depth of the spheres along the camera's pixel rays,
// along the whole ray (t >= 0).
std::vector<double> sphere_optical_depths(const std::vector<Sphere>& spheres, const Camera& camera,
                                          PixelRays sampling = PixelRays::Centres);

// A conservative pixel rectangle [i0, i1) x [j0, j1) of the pixels whose rays (t >= 0) can meet the sphere,
// the bounding box of its silhouette: empty when it lies wholly behind the eye, the whole image when it
// reaches the eye's plane.
void sphere_pixel_rect(const CameraRays& rays, const Sphere& s, int& i0, int& i1, int& j0, int& j1,
                       PixelRays sampling = PixelRays::Centres);

// Cameras looking at the grid along +x, +y and +z, `resolution` pixels square, far enough for the whole
// support to fit. Axis-aligned rays are where the voxel lattice shows most (a sphere cloud's ripple adds
// up coherently along them), so they make a conservative test of any conversion.
std::vector<Camera> grid_axis_views(const DensityGrid& grid, int resolution);

// Three oblique cameras from outside the grid, `resolution` pixels square, that neither the axis views
// nor a fit's own views share: where a conversion is checked on views it never measured against (with
// PixelRays::Jittered, as an estimate of the error from any view).
std::vector<Camera> grid_unseen_views(const DensityGrid& grid, int resolution);

// The grid's optical depth along every pixel ray of a set of views, computed once (the expensive part),
// against which any number of sphere clouds are then measured: a conversion tries several.
class OpticalDepthViews {
public:
    // `threads` 0: every usable CPU.
    OpticalDepthViews(const DensityGrid& grid, double extinction_scale, std::vector<Camera> views, int threads = 0,
                      PixelRays sampling = PixelRays::Centres);

    // Pooled over the rays of every view.
    OpticalDepthError measure(const std::vector<Sphere>& spheres) const;

    const std::vector<Camera>& views() const { return views_; }
    // The grid's optical depth per pixel of view v (row-major, top row first): what a fit is fitted to.
    const std::vector<double>& grid_depths_of(std::size_t v) const { return grid_depths_[v]; }

private:
    std::vector<Camera> views_;
    std::vector<std::vector<double>> grid_depths_;  // per view, per pixel
    int threads_;
    PixelRays sampling_;
};

// One-off measurement over one camera (vdb-import's report, tests).
OpticalDepthError measure_optical_depth_error(const DensityGrid& grid, double extinction_scale,
                                              const std::vector<Sphere>& spheres, const Camera& camera);

}  // namespace brume
