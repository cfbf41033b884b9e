#include "sim/vdb/sphere_fit.h"

#include "sim/camera_rays.h"
#include "sim/parallel_for.h"
#include "sim/vdb/sphere_lattice.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

namespace brume {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kFitViews = 25;  // grid_fit_views
constexpr int kValidationResolution = 64;  // pixels across each of grid_validation_views
// Fitter::merge: pairs closer than this times the smaller radius, extinctions within this factor. Measured
// on the 128^3 cloud (docs/vdb.md): 0.3, 0.5 and 0.8 all merged about as well; 0.5 sits between.
constexpr double kMergeDistance = 0.5;
constexpr double kMergeExtinction = 1.5;
// Rounds at most: the 128^3 cloud at 2% takes 27, and growth of at least 10% a round reaches any cap
// sooner unless merges keep undoing it.
constexpr int kMaxRounds = 80;

// A camera whose view just holds the grid's bounding sphere, looking along `dir`.
Camera view_along(const DensityGrid& grid, glm::dvec3 dir, const glm::dvec3& up, int resolution, double fov_deg = 30.0) {
    const glm::dvec3 lo = grid.support_min(), hi = grid.support_max();
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = 0.5 * glm::length(hi - lo);
    dir = glm::normalize(dir);
    Camera c;
    c.fov_y_deg = fov_deg;
    c.position = centre - dir * (radius / std::sin(c.fov_y_deg * 0.5 * kPi / 180.0));
    c.look_at = centre;
    c.up = up;
    c.width = c.height = resolution;
    return c;
}

// One view's rays and the grid's optical depth along each.
struct FitView {
    CameraRays rays;
    std::vector<glm::dvec3> dirs;  // per pixel, row-major
    std::vector<double> grid;      // per pixel
    std::vector<double> spheres;   // per pixel, the current fit's
};

// A sphere as optimised: its radius and mass as logarithms (both stay positive), extinction derived.
struct Param {
    glm::dvec3 c;
    double log_r;
    double log_m;  // log of extinction * volume
    double tau() const { return std::exp(log_m - std::log(4.0 / 3.0 * kPi) - 3.0 * log_r); }
};

// Adam's moments for the five parameters of one sphere.
struct Moments {
    double m[5] = {0, 0, 0, 0, 0};
    double v[5] = {0, 0, 0, 0, 0};
};

double sphere_mass(const Param& p) { return std::exp(p.log_m); }

class Fitter {
public:
    Fitter(const DensityGrid& grid, const SphereCloudOptions& options) : grid_(grid), options_(options) {
        target_mass_ = grid.mass() * options.extinction_scale;
        max_radius_ = glm::length(grid.support_max() - grid.support_min());
    }

    // The rays to fit to: every pixel of `views`, whose finest fitting view is `resolution` pixels across.
    void set_views(const OpticalDepthViews& views, int resolution) {
        views_.clear();
        grid_sq_ = 0.0;
        for (std::size_t v = 0; v < views.views().size(); ++v) {
            FitView f;
            f.rays = make_camera_rays(views.views()[v]);
            f.grid = views.grid_depths_of(v);
            f.spheres.assign(f.grid.size(), 0.0);
            f.dirs.resize(f.grid.size());
            for (int j = 0; j < f.rays.height; ++j)
                for (int i = 0; i < f.rays.width; ++i)
                    f.dirs[std::size_t(j) * std::size_t(f.rays.width) + std::size_t(i)] = f.rays.pixel_direction(i, j);
            for (const double g : f.grid) grid_sq_ += g * g;
            views_.push_back(std::move(f));
        }
        // Spheres smaller than the ray spacing could fall between the measuring rays, holding mass unseen.
        const glm::dvec3 span = grid_.support_max() - grid_.support_min();
        const double pixel = 1.04 * glm::length(span) / double(resolution);
        min_radius_ = std::max(0.5 * grid_.voxel_size, pixel);
        for (Param& p : params_) p.log_r = std::max(p.log_r, std::log(min_radius_));
    }

    void set(const std::vector<Sphere>& spheres) {
        params_.clear();
        for (const Sphere& s : spheres)
            params_.push_back({s.center, std::log(s.radius), std::log(s.extinction * 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius)});
        conserve_mass();
    }

    std::size_t size() const { return params_.size(); }

    // The relative RMS error of the current spheres over every view (and each view's per-pixel depths).
    double forward() {
        rects_.resize(params_.size() * views_.size());
        parallel_for(views_.size(), options_.threads, [&](std::size_t v, int) { forward_view(v); });
        double d2 = 0.0;
        for (const FitView& f : views_)
            for (std::size_t p = 0; p < f.grid.size(); ++p) d2 += (f.spheres[p] - f.grid[p]) * (f.spheres[p] - f.grid[p]);
        return grid_sq_ > 0.0 ? std::sqrt(d2 / grid_sq_) : 0.0;
    }

    // `iterations` Adam steps, the step size decaying tenfold over them, or fewer: it stops at the first step
    // whose error is within `tolerance`. forward() must have run.
    void optimise(int iterations, double tolerance) {
        std::vector<Moments> moments(params_.size());
        std::vector<std::array<double, 5>> grads(params_.size());
        constexpr double b1 = 0.9, b2 = 0.999, eps = 1e-12;
        for (int it = 0; it < iterations; ++it) {
            gradients(grads, nullptr);
            const double decay = std::pow(0.1, double(it) / double(std::max(1, iterations - 1)));
            const double lr_c = 0.03 * decay, lr_r = 0.03 * decay, lr_t = 0.05 * decay;
            const double c1 = 1.0 - std::pow(b1, it + 1), c2 = 1.0 - std::pow(b2, it + 1);
            for (std::size_t k = 0; k < params_.size(); ++k) {
                Param& p = params_[k];
                Moments& mo = moments[k];
                double step[5];
                for (int q = 0; q < 5; ++q) {
                    mo.m[q] = b1 * mo.m[q] + (1.0 - b1) * grads[k][std::size_t(q)];
                    mo.v[q] = b2 * mo.v[q] + (1.0 - b2) * grads[k][std::size_t(q)] * grads[k][std::size_t(q)];
                    step[q] = (mo.m[q] / c1) / (std::sqrt(mo.v[q] / c2) + eps);
                }
                // Centres move in units of their own radius, so small and large spheres settle alike.
                const double r = std::exp(p.log_r);
                for (int a = 0; a < 3; ++a) p.c[a] -= lr_c * r * step[a];
                p.log_r = std::clamp(p.log_r - lr_r * step[3], std::log(min_radius_), std::log(max_radius_));
                p.log_m -= lr_t * step[4];
            }
            conserve_mass();
            if (forward() <= tolerance) return;
        }
    }

    // Splits the `count` spheres that carry the most absolute residual, each into two at the centroids of the
    // grid's density on either side of the plane across its principal axis; forward() must have run.
    void densify(std::size_t count) {
        std::vector<std::array<double, 5>> grads(params_.size());
        std::vector<double> blame(params_.size(), 0.0);
        gradients(grads, &blame);
        std::vector<std::size_t> order(params_.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return blame[a] > blame[b]; });
        count = std::min(count, order.size());
        std::vector<bool> split(params_.size(), false);
        for (std::size_t n = 0; n < count; ++n) split[order[n]] = true;
        std::vector<Param> next;
        for (std::size_t k = 0; k < params_.size(); ++k) {
            if (!split[k]) {
                next.push_back(params_[k]);
                continue;
            }
            const auto [a, b] = split_sphere(params_[k]);
            next.push_back(a);
            next.push_back(b);
        }
        params_ = std::move(next);
        conserve_mass();
    }

    // Drops spheres holding a negligible share of the mass (they cost fragments and shape nothing).
    void prune() {
        const double total = std::accumulate(params_.begin(), params_.end(), 0.0,
                                             [](double m, const Param& p) { return m + sphere_mass(p); });
        std::erase_if(params_, [&](const Param& p) { return sphere_mass(p) < 1e-6 * total; });
        conserve_mass();
    }

    // Merges pairs of spheres that model the same density: each the other's nearest (by centre distance over
    // the smaller radius), the centres closer than kMergeDistance times the smaller radius, the extinctions
    // within a factor kMergeExtinction. The merged sphere keeps the pair's mass, centre of mass and second
    // moment about it (sum m_i (3/5 r_i^2 + |c_i - c|^2) = 3/5 m R^2). Splits follow the residual, so a
    // region that no longer needs two spheres (its neighbours moved in) would otherwise keep both. Returns
    // the pairs merged.
    std::size_t merge() {
        const std::size_t n = params_.size();
        std::vector<std::size_t> nearest(n, n);
        std::vector<double> radius(n);
        for (std::size_t k = 0; k < n; ++k) radius[k] = std::exp(params_[k].log_r);
        // All pairs, squared: a few thousand spheres take milliseconds (an exp per pair took a second a round).
        parallel_for(n, options_.threads, [&](std::size_t a, int) {
            double best = kMergeDistance * kMergeDistance;
            for (std::size_t b = 0; b < n; ++b) {
                if (b == a) continue;
                const glm::dvec3 d = params_[a].c - params_[b].c;
                const double r = std::min(radius[a], radius[b]);
                const double q = glm::dot(d, d) / (r * r);
                if (q < best) best = q, nearest[a] = b;
            }
        });
        std::vector<Param> next;
        std::vector<bool> gone(n, false);
        std::size_t merged = 0;
        for (std::size_t a = 0; a < n; ++a) {
            const std::size_t b = nearest[a];
            if (gone[a]) continue;
            if (b < n && b > a && nearest[b] == a && !gone[b]) {
                const Param& p = params_[a];
                const Param& q = params_[b];
                const double ratio = p.tau() / q.tau();
                if (ratio < kMergeExtinction && ratio > 1.0 / kMergeExtinction) {
                    const double mp = sphere_mass(p), mq = sphere_mass(q), m = mp + mq;
                    Param u = p;
                    u.c = (mp * p.c + mq * q.c) / m;
                    const double rp = std::exp(p.log_r), rq = std::exp(q.log_r);
                    const double dp = glm::dot(p.c - u.c, p.c - u.c), dq = glm::dot(q.c - u.c, q.c - u.c);
                    const double r2 = (mp * (rp * rp + 5.0 / 3.0 * dp) + mq * (rq * rq + 5.0 / 3.0 * dq)) / m;
                    u.log_r = std::clamp(0.5 * std::log(r2), std::log(min_radius_), std::log(max_radius_));
                    u.log_m = std::log(m);
                    next.push_back(u);
                    gone[b] = true;
                    ++merged;
                    continue;
                }
            }
            next.push_back(params_[a]);
        }
        params_ = std::move(next);
        conserve_mass();
        return merged;
    }

    std::vector<Sphere> spheres() const {
        std::vector<Sphere> out;
        for (const Param& p : params_) {
            Sphere s;
            s.center = p.c;
            s.radius = std::exp(p.log_r);
            s.extinction = p.tau();
            s.albedo = options_.albedo;
            if (options_.albedo_grid) s.albedo *= std::clamp(options_.albedo_grid->sample(s.center), 0.0, 1.0);
            out.push_back(s);
        }
        return out;
    }

private:
    // Also records each sphere's pixel rectangle in this view, which gradients() reads: the spheres do not
    // move between a forward pass and the gradients that follow it.
    void forward_view(std::size_t v) {
        FitView& f = views_[v];
        std::fill(f.spheres.begin(), f.spheres.end(), 0.0);
        for (std::size_t k = 0; k < params_.size(); ++k) {
            const Param& p = params_[k];
            const Sphere s{p.c, std::exp(p.log_r), p.tau()};
            Rect& rect = rects_[k * views_.size() + v];
            sphere_pixel_rect(f.rays, s, rect.i0, rect.i1, rect.j0, rect.j1);
            const int i0 = rect.i0, i1 = rect.i1, j0 = rect.j0, j1 = rect.j1;
            const glm::dvec3 oc = s.center - f.rays.eye;
            const double oc2 = glm::dot(oc, oc), r2 = s.radius * s.radius;
            for (int j = j0; j < j1; ++j)
                for (int i = i0; i < i1; ++i) {
                    const std::size_t px = std::size_t(j) * std::size_t(f.rays.width) + std::size_t(i);
                    const double b = glm::dot(oc, f.dirs[px]);
                    const double h2 = r2 - (oc2 - b * b);
                    if (h2 <= 0.0) continue;
                    const double h = std::sqrt(h2);
                    f.spheres[px] += s.extinction * (std::max(0.0, b + h) - std::max(0.0, b - h));
                }
        }
    }

    // d(error^2)/d(c, log r, log tau) per sphere; with `blame`, each sphere's share of sum |residual|.
    // Each sphere's sums run over views and pixels in order, so the result is the same on any thread count.
    void gradients(std::vector<std::array<double, 5>>& grads, std::vector<double>* blame) const {
        const double norm = grid_sq_ > 0.0 ? 2.0 / grid_sq_ : 0.0;
        parallel_for(params_.size(), options_.threads, [&](std::size_t k, int) {
            const Param& p = params_[k];
            const Sphere s{p.c, std::exp(p.log_r), p.tau()};
            const double r2 = s.radius * s.radius;
            // Chords have infinite slope where rays graze the sphere; a floor on the half chord keeps a few
            // grazing rays from steering the whole sphere.
            const double h_floor = 0.05 * s.radius;
            glm::dvec3 g_c(0.0);
            double g_r = 0.0, g_t = 0.0, share = 0.0;
            for (std::size_t v = 0; v < views_.size(); ++v) {
                const FitView& f = views_[v];
                const Rect& rect = rects_[k * views_.size() + v];
                const int i0 = rect.i0, i1 = rect.i1, j0 = rect.j0, j1 = rect.j1;
                const glm::dvec3 oc = s.center - f.rays.eye;
                const double oc2 = glm::dot(oc, oc);
                for (int j = j0; j < j1; ++j)
                    for (int i = i0; i < i1; ++i) {
                        const std::size_t px = std::size_t(j) * std::size_t(f.rays.width) + std::size_t(i);
                        const glm::dvec3& d = f.dirs[px];
                        const double b = glm::dot(oc, d);
                        const double h2 = r2 - (oc2 - b * b);
                        if (h2 <= 0.0 || b - std::sqrt(h2) < 0.0) continue;  // missed, or holds the eye
                        const double h = std::sqrt(h2), hg = std::max(h, h_floor);
                        const double res = f.spheres[px] - f.grid[px];
                        const double w = norm * res;
                        g_t += w * 2.0 * h;
                        g_r += w * s.extinction * 2.0 * s.radius / hg;
                        g_c += w * s.extinction * (-2.0 / hg) * (oc - b * d);
                        if (blame && f.spheres[px] > 0.0) share += std::abs(res) * s.extinction * 2.0 * h / f.spheres[px];
                    }
            }
            // Radius at fixed mass (tau ~ r^-3, so d tau / d log r = -3 tau), and log mass: shape and amount
            // apart, so that the global mass rescale does not fight the radius (at fixed tau, too much depth
            // would shrink r while the rescale raised tau, collapsing spheres between the rays).
            grads[k] = {g_c.x, g_c.y, g_c.z, g_r * s.radius - 3.0 * g_t * s.extinction, g_t * s.extinction};
            if (blame) (*blame)[k] = share;
        });
    }

    // Two children along the principal axis of the grid's density inside the sphere, at the density
    // centroids of either half, each with its half's share of the mass. A sphere over no density splits
    // along x about its centre.
    std::pair<Param, Param> split_sphere(const Param& p) const {
        const double r = std::exp(p.log_r);
        const double mass = sphere_mass(p);
        glm::dvec3 axis(1.0, 0.0, 0.0), centre = p.c;
        const auto voxels = [&](auto&& body) {
            const glm::dvec3 lo = (p.c - r - grid_.origin) / grid_.voxel_size - glm::dvec3(grid_.min);
            const glm::dvec3 hi = (p.c + r - grid_.origin) / grid_.voxel_size - glm::dvec3(grid_.min);
            const glm::ivec3 a = glm::max(glm::ivec3(glm::ceil(lo)), glm::ivec3(0));
            const glm::ivec3 b = glm::min(glm::ivec3(glm::floor(hi)), grid_.size - 1);
            // Every stride-th voxel, at most about 32 across the sphere: the split only needs the density's
            // centroids and principal axis, and a whole-grid sphere of a 256^3 grid holds 10^7 voxels.
            const int stride = std::max(1, int(std::ceil(2.0 * r / grid_.voxel_size / 32.0)));
            for (int k = a.z; k <= b.z; k += stride)
                for (int j = a.y; j <= b.y; j += stride)
                    for (int i = a.x; i <= b.x; i += stride) {
                        const double v = grid_.at(i, j, k);
                        if (v <= 0.0) continue;
                        const glm::dvec3 x = grid_.voxel_center(glm::dvec3(i, j, k));
                        if (glm::dot(x - p.c, x - p.c) <= r * r) body(x, v);
                    }
        };
        double w = 0.0;
        glm::dvec3 sum(0.0);
        voxels([&](const glm::dvec3& x, double v) { w += v, sum += v * x; });
        if (w > 0.0) {
            centre = sum / w;
            double cov[3][3] = {};
            voxels([&](const glm::dvec3& x, double v) {
                const glm::dvec3 d = x - centre;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) cov[a][b] += v * d[a] * d[b];
            });
            // Power iteration from a fixed start that no axis-symmetric cell is orthogonal to.
            glm::dvec3 e = glm::normalize(glm::dvec3(1.0, 0.71, 0.37));
            for (int it = 0; it < 30; ++it) {
                glm::dvec3 n(0.0);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) n[a] += cov[a][b] * e[b];
                if (glm::length(n) <= 0.0) break;
                e = glm::normalize(n);
            }
            axis = e;
        }
        double wa = 0.0, wb = 0.0;
        glm::dvec3 sa(0.0), sb(0.0);
        voxels([&](const glm::dvec3& x, double v) {
            if (glm::dot(x - centre, axis) < 0.0) wa += v, sa += v * x;
            else wb += v, sb += v * x;
        });
        const double child_r = 0.75 * r;
        Param a = p, b = p;
        a.c = wa > 0.0 ? sa / wa : centre - 0.5 * r * axis;
        b.c = wb > 0.0 ? sb / wb : centre + 0.5 * r * axis;
        const double fa = wa + wb > 0.0 ? std::clamp(wa / (wa + wb), 0.05, 0.95) : 0.5;
        a.log_r = b.log_r = std::log(std::max(child_r, min_radius_));
        a.log_m = std::log(mass * fa);
        b.log_m = std::log(mass * (1.0 - fa));
        return {a, b};
    }

    // Every sphere's extinction scaled by one factor so that the total equals the grid's mass.
    void conserve_mass() {
        double m = 0.0;
        for (const Param& p : params_) m += sphere_mass(p);
        if (!(m > 0.0)) return;
        const double shift = std::log(target_mass_ / m);
        for (Param& p : params_) p.log_m += shift;
    }

    const DensityGrid& grid_;
    const SphereCloudOptions& options_;
    std::vector<FitView> views_;
    std::vector<Param> params_;
    // Per sphere, per view (sphere-major): the pixels forward() found it may cover.
    struct Rect {
        int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    };
    std::vector<Rect> rects_;
    double grid_sq_ = 0.0;
    double target_mass_ = 0.0;
    double min_radius_ = 0.0, max_radius_ = 0.0;
};

// The coarsest resampled lattice of at most `count` spheres (its count falls as the spacing grows), its
// spheres 1.25 times their cell's equal-volume radius: a seed that covers the density without much spill.
std::vector<Sphere> seed_lattice(const DensityGrid& grid, SphereCloudOptions options, std::size_t count) {
    options.sphere_scale = 1.25;
    const double largest = double(std::max({grid.size.x, grid.size.y, grid.size.z})) + 2.0;
    double lo = 1.0001, hi = largest;
    if (grid_to_lattice_spheres(grid, options, lo).size() <= count) return grid_to_lattice_spheres(grid, options, lo);
    while (grid_to_lattice_spheres(grid, options, hi).size() > count) hi *= 1.5;
    for (int step = 0; step < 20 && hi / lo > 1.001; ++step) {
        const double mid = std::sqrt(lo * hi);
        (grid_to_lattice_spheres(grid, options, mid).size() > count ? lo : hi) = mid;
    }
    return grid_to_lattice_spheres(grid, options, hi);
}

void check(const SphereCloudOptions& o, const SphereFitSettings& s) {
    if (!(o.tolerance > 0.0 && o.tolerance <= 1.0))
        throw std::invalid_argument("tolerance must be in (0, 1] (got " + std::to_string(o.tolerance) + ")");
    if (!(std::isfinite(o.extinction_scale) && o.extinction_scale > 0.0))
        throw std::invalid_argument("extinction scale must be positive and finite");
    if (s.seed_spheres < 1 || s.iterations < 1 || !(s.growth > 1.0 && s.growth <= 8.0) || s.view_resolution < 8 ||
        s.view_resolution > 1024)
        throw std::invalid_argument("fit settings out of range (seed >= 1, iterations >= 1, growth in (1, 8], views 8-1024 px)");
}

}  // namespace

std::vector<Camera> grid_fit_views(const DensityGrid& grid, int resolution) {
    std::vector<Camera> views = grid_axis_views(grid, resolution);
    // A Fibonacci spiral over the hemisphere z > 0 (a view from -d sees nearly the rays a view from d does):
    // evenly spread directions, the more of them the fewer lines of sight a fit can match and miss the grid.
    constexpr double golden = 2.39996322972865332;  // pi (3 - sqrt 5)
    for (int k = 0; k < kFitViews - 3; ++k) {
        const double z = 1.0 - (k + 0.5) / double(kFitViews - 3);
        const double rho = std::sqrt(1.0 - z * z), phi = golden * k;
        const glm::dvec3 d(rho * std::cos(phi), rho * std::sin(phi), z);
        const glm::dvec3 up = std::abs(d.y) > 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        views.push_back(view_along(grid, d, up, resolution));
    }
    return views;
}

std::vector<Camera> grid_validation_views(const DensityGrid& grid, int resolution) {
    // Eight directions over the whole sphere (a Fibonacci spiral, turned half a step from the fitting
    // views'), seen from close by with a wide lens (fov 50, the bounding sphere just in view) so that their
    // rays cross the grid at other angles than the fitting views' nearly parallel ones.
    std::vector<Camera> views;
    constexpr double golden = 2.39996322972865332;
    constexpr int n = 8;
    for (int k = 0; k < n; ++k) {
        const double z = 1.0 - 2.0 * (k + 0.5) / double(n);
        const double rho = std::sqrt(1.0 - z * z), phi = golden * (k + 0.5);
        const glm::dvec3 d(rho * std::cos(phi), rho * std::sin(phi), z);
        const glm::dvec3 up = std::abs(d.y) > 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        views.push_back(view_along(grid, d, up, resolution, 50.0));
    }
    return views;
}

SphereFit fit_spheres(const DensityGrid& grid, const SphereCloudOptions& options, const SphereFitSettings& settings,
                      const std::function<void(const SphereFitProgress&)>& progress) {
    check(options, settings);
    SphereFit out;
    if (grid.values.empty() || *std::max_element(grid.values.begin(), grid.values.end()) == 0.0f) return out;
    const auto start = std::chrono::steady_clock::now();
    // Without an explicit cap: kDefaultFitSphereCap, and never more than one sphere per 8 active voxels, past
    // which a tiling (one sphere per voxel at most) is the cheaper answer.
    const std::size_t cap = options.max_spheres > 0
                                ? options.max_spheres
                                : std::clamp<std::size_t>(std::size_t(grid.active_voxels / 8), 1, kDefaultFitSphereCap);
    // The fitting views, rebuilt finer as the spheres multiply: at least kRaysPerParameter rays for each of a
    // sphere's five parameters, or the fit would match the views it sees and not the grid between them.
    constexpr double kRaysPerParameter = 12.0;
    const auto resolution_for = [&](std::size_t spheres) {
        const int needed = int(std::ceil(std::sqrt(kRaysPerParameter * 5.0 * double(spheres) / double(kFitViews)) / 16.0)) * 16;
        return std::clamp(needed, settings.view_resolution, std::max(settings.view_resolution, 256));
    };
    int resolution = 0;
    std::unique_ptr<OpticalDepthViews> views;
    Fitter fitter(grid, options);
    const auto use_views = [&](int r) {
        std::vector<Camera> cameras = grid_fit_views(grid, r);
        cameras.insert(cameras.end(), options.views.begin(), options.views.end());
        views = std::make_unique<OpticalDepthViews>(grid, options.extinction_scale, cameras, options.threads);
        resolution = r;
        fitter.set_views(*views, r);
    };
    // Held out from the gradients, these views decide when to stop: the training views alone are matched
    // a little better than the grid between them (at 2%, 2.57% from unseen views), so the fit also has to
    // measure within kValidationMargin of the tolerance on views it is not fitted to.
    const OpticalDepthViews validation(grid, options.extinction_scale, grid_validation_views(grid, kValidationResolution),
                                       options.threads, PixelRays::Jittered);
    use_views(resolution_for(settings.seed_spheres));
    fitter.set(seed_lattice(grid, options, std::min(settings.seed_spheres, cap)));
    fitter.forward();
    double previous_error = 0.0;
    std::size_t previous_spheres = 0;
    // What a round's steps aim at over the fitting views: the tolerance, lowered by the gap the held-out views
    // show once the fitting views meet it and they do not (otherwise every later round would stop at its first
    // step, the fitting views already within tolerance, and only the splits would lower the held-out error).
    double target = options.tolerance;
    bool reached_cap = false;
    for (int round = 1;; ++round) {
        fitter.optimise(settings.iterations, target);
        fitter.prune();
        const double error = fitter.forward();
        const double held_out = validation.measure(fitter.spheres()).relative_rms;
        out.rounds = round;
        out.validation_error = held_out;
        if (progress)
            progress({round, fitter.size(), error, held_out,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
        out.met_tolerance = error <= options.tolerance && held_out <= kValidationMargin * options.tolerance;
        // Done at the tolerance, or once a round has been fitted with the whole budget: a densification that
        // reached the cap (merges may have taken a few spheres back since; without this the fit would go
        // on splitting and merging at the cap), or kMaxRounds, a bound on the time whatever the grid.
        if (out.met_tolerance || fitter.size() >= cap || reached_cap || round >= kMaxRounds) break;
        if (error <= target && held_out > kValidationMargin * options.tolerance)
            target = std::min(target, error * kValidationMargin * options.tolerance / held_out);
        // The growth below aims at whichever of the two is further from its goal.
        const double behind = std::max(error, held_out / kValidationMargin);
        // Error falls about as a power of the count (docs/vdb.md): near the tolerance, grow by what that power
        // predicts (with a 10% margin) rather than a whole growth step, so the count overshoots less.
        double factor = settings.growth;
        if (previous_error > behind && previous_spheres < fitter.size()) {
            const double power = std::log(previous_error / behind) / std::log(double(fitter.size()) / double(previous_spheres));
            if (power > 0.05) factor = std::clamp(1.1 * std::pow(behind / options.tolerance, 1.0 / power), 1.1, settings.growth);
        }
        previous_error = behind;
        previous_spheres = fitter.size();
        const std::size_t grown =
            std::min(cap, std::max(fitter.size() + 1, std::size_t(std::ceil(double(fitter.size()) * factor))));
        fitter.densify(grown - fitter.size());
        reached_cap = grown >= cap;
        if (settings.merge) fitter.merge();
        if (resolution_for(grown) > resolution) use_views(resolution_for(grown));
        fitter.forward();
    }
    out.spheres = fitter.spheres();
    out.error = views->measure(out.spheres);
    return out;
}

SphereCloud fit_sphere_cloud(const DensityGrid& grid, const SphereCloudOptions& options,
                             const std::function<void(const SphereFitProgress&)>& progress) {
    const SphereFit fit = fit_spheres(grid, options, {}, progress);
    if (!fit.met_tolerance && options.max_spheres == 0 && !fit.spheres.empty()) {
        char text[512];
        std::snprintf(text, sizeof text,
                      "fitting stopped at %zu spheres (the default cap: %zu, or one per 8 active voxels) at %.3g%% RMS "
                      "optical-depth error, above the tolerance %.3g%%; raise the tolerance, allow more spheres "
                      "(max_spheres), or tile (no fit)",
                      fit.spheres.size(), kDefaultFitSphereCap, 100.0 * fit.error.relative_rms, 100.0 * options.tolerance);
        throw std::runtime_error(text);
    }
    SphereCloud cloud;
    cloud.spheres = fit.spheres;
    cloud.error = fit.error;
    cloud.fitted = true;
    cloud.fit_rounds = fit.rounds;
    cloud.met_tolerance = fit.met_tolerance;
    return cloud;
}

SphereCloud convert_grid(const DensityGrid& grid, const SphereCloudOptions& options,
                         const std::function<void(const SphereFitProgress&)>& progress) {
    return options.fit ? fit_sphere_cloud(grid, options, progress) : grid_to_spheres(grid, options);
}

}  // namespace brume
