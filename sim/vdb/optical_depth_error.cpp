#include "sim/vdb/optical_depth_error.h"

#include "sim/camera_rays.h"
#include "sim/parallel_for.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {

namespace {

// The ray's parameter interval inside an axis-aligned box; empty when t1 <= t0.
void clip_to_box(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi, double& t0,
                 double& t1) {
    t0 = 0.0;
    t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) t1 = -1.0;
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
}

}  // namespace

// The sphere's silhouette bounded exactly: in the camera's (right, forward) plane the planes through the
// eye that hold the up axis and touch the sphere have slopes u = x/z solving (x - u z)^2 = r^2 (1 + u^2),
// and likewise for up. A bound on the silhouette rather than on its bounding cube's projection: for the
// few-pixel spheres of a fit, the cube's corners and a pixel of slack held three to four times the pixels
// the sphere covers, and every one was tested (docs/vdb.md "Fitting time"). The whole image when the sphere
// reaches the eye's plane.
void sphere_pixel_rect(const CameraRays& rays, const Sphere& s, int& i0, int& i1, int& j0, int& j1, PixelRays sampling) {
    const glm::dvec3 v = s.center - rays.eye;
    const double z = glm::dot(v, rays.forward);
    // Wholly behind the eye: no ray (t >= 0) meets it. (A camera inside a cloud has half the cloud there.)
    if (z < -s.radius) {
        i0 = i1 = j0 = j1 = 0;
        return;
    }
    i0 = 0, i1 = rays.width, j0 = 0, j1 = rays.height;
    const double r = s.radius;
    const double z2r2 = z * z - r * r;
    if (!(z > r) || !(z2r2 > 1e-9 * z * z)) return;
    const double sx = glm::length(rays.right), sy = glm::length(rays.up);
    const double x = glm::dot(v, rays.right) / sx, y = glm::dot(v, rays.up) / sy;
    const auto slopes = [&](double a, double& lo, double& hi) {
        const double root = r * std::sqrt(std::max(0.0, a * a + z2r2));
        lo = (a * z - root) / z2r2;
        hi = (a * z + root) / z2r2;
    };
    double ux_lo, ux_hi, uy_lo, uy_hi;
    slopes(x, ux_lo, ux_hi);
    slopes(y, uy_lo, uy_hi);
    const double x_lo = (ux_lo / sx + 1.0) * 0.5 * rays.width, x_hi = (ux_hi / sx + 1.0) * 0.5 * rays.width;
    const double y_lo = (1.0 - uy_hi / sy) * 0.5 * rays.height, y_hi = (1.0 - uy_lo / sy) * 0.5 * rays.height;
    // Pixel i's ray passes through i + 0.5 (jittered: anywhere in [i, i + 1)); a hundredth of a pixel of
    // slack for rounding in the rays.
    const double slack = sampling == PixelRays::Jittered ? 0.51 : 0.01;
    const auto first = [&](double lo, int n) { return int(std::clamp(std::ceil(lo - 0.5 - slack), 0.0, double(n))); };
    const auto end = [&](double hi, int n) { return int(std::clamp(std::floor(hi - 0.5 + slack) + 1.0, 0.0, double(n))); };
    i0 = first(x_lo, rays.width), i1 = std::max(i0, end(x_hi, rays.width));
    j0 = first(y_lo, rays.height), j1 = std::max(j0, end(y_hi, rays.height));
}

namespace {

// A fixed pseudo-random number in [0, 1) for x (an integer hash, so every thread count and run agrees).
double hash_unit(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return double(x >> 8) * (1.0 / 16777216.0);
}

}  // namespace

glm::dvec3 pixel_ray(const CameraRays& rays, int i, int j, PixelRays sampling) {
    if (sampling == PixelRays::Centres) return rays.pixel_direction(i, j);
    const std::uint32_t index = std::uint32_t(j) * std::uint32_t(rays.width) + std::uint32_t(i);
    return rays.direction(i + hash_unit(2u * index), j + hash_unit(2u * index + 1u));
}

double grid_optical_depth(const DensityGrid& grid, double extinction_scale, const glm::dvec3& origin,
                          const glm::dvec3& unit_dir) {
    double t0, t1;
    clip_to_box(origin, unit_dir, grid.support_min(), grid.support_max(), t0, t1);
    if (!(t1 > t0)) return 0.0;
    // Breakpoints: where the ray crosses a plane of voxel centres. Between two the field is a cubic in t.
    std::vector<double> ts{t0, t1};
    for (int a = 0; a < 3; ++a) {
        if (unit_dir[a] == 0.0) continue;
        const double q0 = (origin[a] + t0 * unit_dir[a] - grid.origin[a]) / grid.voxel_size;
        const double q1 = (origin[a] + t1 * unit_dir[a] - grid.origin[a]) / grid.voxel_size;
        for (double q = std::ceil(std::min(q0, q1)); q <= std::max(q0, q1); q += 1.0) {
            const double t = (grid.origin[a] + q * grid.voxel_size - origin[a]) / unit_dir[a];
            if (t > t0 && t < t1) ts.push_back(t);
        }
    }
    std::sort(ts.begin(), ts.end());
    double sum = 0.0;
    double f_prev = grid.sample(origin + ts[0] * unit_dir);
    for (std::size_t k = 1; k < ts.size(); ++k) {
        const double h = ts[k] - ts[k - 1];
        if (h <= 0.0) continue;
        const double f_mid = grid.sample(origin + (ts[k - 1] + 0.5 * h) * unit_dir);
        const double f_next = grid.sample(origin + ts[k] * unit_dir);
        sum += h / 6.0 * (f_prev + 4.0 * f_mid + f_next);  // Simpson: exact for the cubic
        f_prev = f_next;
    }
    return sum * extinction_scale;
}

std::vector<double> sphere_optical_depths(const std::vector<Sphere>& spheres, const Camera& camera, PixelRays sampling) {
    const CameraRays rays = make_camera_rays(camera);
    std::vector<double> depth(std::size_t(rays.width) * std::size_t(rays.height), 0.0);
    for (const Sphere& s : spheres) {
        int i0, i1, j0, j1;
        sphere_pixel_rect(rays, s, i0, i1, j0, j1, sampling);
        for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i) {
                const glm::dvec3 d = pixel_ray(rays, i, j, sampling);
                const glm::dvec3 oc = s.center - rays.eye;
                const double b = glm::dot(oc, d);
                const double h2 = s.radius * s.radius - (glm::dot(oc, oc) - b * b);
                if (h2 <= 0.0) continue;
                const double h = std::sqrt(h2);
                const double chord = std::max(0.0, b + h) - std::max(0.0, b - h);  // clipped to t >= 0
                depth[std::size_t(j) * std::size_t(rays.width) + std::size_t(i)] += s.extinction * chord;
            }
    }
    return depth;
}

namespace {

std::vector<double> grid_depths(const DensityGrid& grid, double extinction_scale, const Camera& camera, int threads,
                                PixelRays sampling) {
    const CameraRays rays = make_camera_rays(camera);
    std::vector<double> depth(std::size_t(rays.width) * std::size_t(rays.height), 0.0);
    parallel_for(std::size_t(rays.height), threads, [&](std::size_t row, int) {
        const int j = int(row);
        for (int i = 0; i < rays.width; ++i)
            depth[std::size_t(j) * std::size_t(rays.width) + std::size_t(i)] =
                grid_optical_depth(grid, extinction_scale, rays.eye, pixel_ray(rays, i, j, sampling));
    });
    return depth;
}

struct ErrorSums {
    double d2 = 0.0, g2 = 0.0, d = 0.0, g = 0.0, max_d = 0.0, max_g = 0.0, dt = 0.0;
    long rays = 0;
    void add(double grid, double spheres) {
        if (grid == 0.0 && spheres == 0.0) return;
        ++rays;
        const double diff = spheres - grid;
        dt += std::abs(std::exp(-spheres) - std::exp(-grid));
        d2 += diff * diff, g2 += grid * grid, d += diff, g += grid;
        max_d = std::max(max_d, std::abs(diff));
        max_g = std::max(max_g, grid);
    }
    OpticalDepthError result() const {
        OpticalDepthError e;
        e.rays = rays;
        e.max_grid_depth = max_g;
        if (g > 0.0) {
            e.relative_rms = std::sqrt(d2 / g2);
            e.relative_max = max_d / max_g;
            e.bias = d / g;
            e.absolute_rms = std::sqrt(d2 / double(rays)) / max_g;
        } else if (rays > 0) {
            e.relative_rms = e.relative_max = e.bias = e.absolute_rms = std::numeric_limits<double>::infinity();  // depth where none is
        }
        if (rays > 0) e.transmittance_mean = dt / double(rays);
        return e;
    }
};

}  // namespace

std::vector<Camera> grid_axis_views(const DensityGrid& grid, int resolution) {
    const glm::dvec3 lo = grid.support_min(), hi = grid.support_max();
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = 0.5 * glm::length(hi - lo);
    std::vector<Camera> views;
    const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const glm::dvec3 ups[3] = {{0, 1, 0}, {0, 0, 1}, {0, 1, 0}};
    for (int a = 0; a < 3; ++a) {
        Camera c;
        c.fov_y_deg = 30.0;
        // The bounding sphere just fits the view, so every ray that can meet the grid is a pixel ray.
        c.position = centre - axes[a] * (radius / std::sin(c.fov_y_deg * 0.5 * 3.14159265358979323846 / 180.0));
        c.look_at = centre;
        c.up = ups[a];
        c.width = c.height = resolution;
        views.push_back(c);
    }
    return views;
}

OpticalDepthViews::OpticalDepthViews(const DensityGrid& grid, double extinction_scale, std::vector<Camera> views,
                                     int threads, PixelRays sampling)
    : views_(std::move(views)), threads_(threads), sampling_(sampling) {
    for (const Camera& c : views_) grid_depths_.push_back(grid_depths(grid, extinction_scale, c, threads_, sampling_));
}

OpticalDepthError OpticalDepthViews::measure(const std::vector<Sphere>& spheres) const {
    std::vector<std::vector<double>> sphere_depths(views_.size());
    parallel_for(views_.size(), threads_, [&](std::size_t v, int) { sphere_depths[v] = sphere_optical_depths(spheres, views_[v], sampling_); });
    ErrorSums sums;
    for (std::size_t v = 0; v < views_.size(); ++v)
        for (std::size_t p = 0; p < grid_depths_[v].size(); ++p) sums.add(grid_depths_[v][p], sphere_depths[v][p]);
    return sums.result();
}

OpticalDepthError measure_optical_depth_error(const DensityGrid& grid, double extinction_scale,
                                              const std::vector<Sphere>& spheres, const Camera& camera) {
    return OpticalDepthViews(grid, extinction_scale, {camera}).measure(spheres);
}

std::vector<Camera> grid_unseen_views(const DensityGrid& grid, int resolution) {
    std::vector<Camera> views;
    const glm::dvec3 centre = 0.5 * (grid.support_min() + grid.support_max());
    const double radius = 0.5 * glm::length(grid.support_max() - grid.support_min());
    const glm::dvec3 dirs[3] = {{0.3, 0.8, -0.5}, {-0.9, 0.2, 0.4}, {0.1, -0.45, -0.9}};
    for (const glm::dvec3& d : dirs) {
        Camera c;
        c.position = centre + glm::normalize(d) * (2.5 * radius);
        c.look_at = centre;
        c.up = {0, 0, 1};
        c.fov_y_deg = 50.0;
        c.width = c.height = resolution;
        views.push_back(c);
    }
    return views;
}

}  // namespace brume
