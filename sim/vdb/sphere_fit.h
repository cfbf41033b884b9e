// A density grid as the fewest spheres that meet a tolerance, found by fitting rather than tiling
// (docs/vdb.md "Fitting"). The tiling conversion (sim/vdb/sphere_cloud.h) places one sphere per cell, so
// a shape that is simple in spheres costs as much as any other of its size; here the spheres' centres,
// radii and extinctions are optimised (Adam) against the exact optical depth of the trilinear grid along
// the pixel rays of 25 measuring views, the very error the tolerance bounds. It starts from the
// coarsest resampled lattice (sim/vdb/sphere_lattice.h) of a few spheres and, round by round, splits the
// spheres that carry the most residual, as 3D Gaussian splatting densifies, merges pairs that have come
// to model the same density, and prunes nearly empty ones, until the error is within tolerance (on the
// fitting views and on held-out ones) or the sphere budget is spent.
//
// Invariants: the spheres' extinction mass equals the grid's (a global rescale after every step), every
// radius and extinction stays positive (they are optimised as logarithms), and the result depends only on
// the input (every sum runs in a fixed order whatever the thread count).
#pragma once

#include "sim/density_grid.h"
#include "sim/scene.h"
#include "sim/vdb/optical_depth_error.h"
#include "sim/vdb/sphere_cloud.h"

#include <cstddef>
#include <functional>
#include <vector>

namespace brume {

// With no --max-spheres, fitting gives up past this many spheres, or one per 8 active voxels if fewer:
// fitting costs grow with the count and a tiling (grid_to_spheres) is the better tool for clouds that
// need more.
inline constexpr std::size_t kDefaultFitSphereCap = 20'000;

struct SphereFitSettings {
    std::size_t seed_spheres = 1;  // the seed lattice's size, at most
    int iterations = 60;           // Adam steps per round
    double growth = 1.5;           // sphere count multiplier per densification round
    // Pixels across each of the fitting views, at least; finer as the spheres multiply (sphere_fit.cpp).
    int view_resolution = 48;
    bool merge = true;  // merge pairs of spheres that model the same density after each round's splits
};

struct SphereFitProgress {
    int round = 0;
    std::size_t spheres = 0;
    double error = 0.0;  // relative RMS optical-depth error over the fitting views after the round
    double validation = 0.0;  // the same over grid_validation_views, which the gradients never see
    double seconds = 0.0;
};

struct SphereFit {
    std::vector<Sphere> spheres;
    OpticalDepthError error;  // over every fitting view
    double validation_error = 0.0;  // relative RMS over grid_validation_views
    int rounds = 0;
    bool met_tolerance = false;
};

// Twenty-five views of the grid: the three axis views (sim/vdb/optical_depth_error.h) and 22 spread evenly
// over a hemisphere of directions. A fit matches what its views see, so the more directions the fewer
// ways it has to match them and miss the grid in between (issue 13: within 1.25x on unseen views).
std::vector<Camera> grid_fit_views(const DensityGrid& grid, int resolution);

// A fit is done when its error over the fitting views is within the tolerance and its error over these
// held-out views within this multiple of it (issue 13: within 1.25x on views the fit never saw).
inline constexpr double kValidationMargin = 1.2;

// Eight perspective views from close by, spread over every direction, that a fit measures itself on but
// is never fitted to: the views that decide when it stops. Neither these nor the fitting views are
// grid_unseen_views (sim/vdb/optical_depth_error.h), on which tests and bench vdb check the result.
std::vector<Camera> grid_validation_views(const DensityGrid& grid, int resolution);

// Fits spheres to the grid over grid_fit_views plus options.views. Uses options.tolerance (required, in
// (0, 1]), options.max_spheres (0: kDefaultFitSphereCap), extinction_scale, albedo, albedo_grid (sampled at
// each centre) and threads; stops at the first round within tolerance (and within kValidationMargin of it
// on grid_validation_views) or at the sphere cap, whichever comes first, and reports which (met_tolerance). Throws std::invalid_argument for options out of range.
// An all-zero grid gives no spheres. `progress`, when set, is called after every round.
SphereFit fit_spheres(const DensityGrid& grid, const SphereCloudOptions& options, const SphereFitSettings& settings = {},
                      const std::function<void(const SphereFitProgress&)>& progress = {});

// fit_spheres as a conversion result: the fit's spheres and error, with fitted, fit_rounds and met_tolerance
// set. A fit that ran into the default cap (no max_spheres) above the tolerance is an error, a
// std::runtime_error naming what it reached; one stopped by an explicit max_spheres is a result.
SphereCloud fit_sphere_cloud(const DensityGrid& grid, const SphereCloudOptions& options,
                             const std::function<void(const SphereFitProgress&)>& progress = {});

// options.fit ? fit_sphere_cloud : grid_to_spheres: the conversion a [[vdb]] table or vdb-import asks for.
SphereCloud convert_grid(const DensityGrid& grid, const SphereCloudOptions& options,
                         const std::function<void(const SphereFitProgress&)>& progress = {});

}  // namespace brume
