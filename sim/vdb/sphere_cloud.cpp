#include "sim/vdb/sphere_cloud.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brume {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A box of voxels, local indices [lo, lo + extent).
struct Cell {
    glm::ivec3 lo;
    glm::ivec3 extent;
};

struct CellStats {
    float min = 0.0f;
    float max = 0.0f;
    double sum = 0.0;
};

CellStats stats(const DensityGrid& grid, const Cell& c) {
    CellStats s{grid.at(c.lo.x, c.lo.y, c.lo.z), grid.at(c.lo.x, c.lo.y, c.lo.z), 0.0};
    for (int k = c.lo.z; k < c.lo.z + c.extent.z; ++k)
        for (int j = c.lo.y; j < c.lo.y + c.extent.y; ++j) {
            const float* row = &grid.values[grid.offset(c.lo.x, j, k)];
            for (int i = 0; i < c.extent.x; ++i) {
                s.min = std::min(s.min, row[i]);
                s.max = std::max(s.max, row[i]);
                s.sum += double(row[i]);
            }
        }
    return s;
}

class Builder {
public:
    Builder(const DensityGrid& grid, const SphereCloudOptions& options, double tolerance, bool count_only)
        : grid_(grid), options_(options), count_only_(count_only) {
        const float grid_max = grid.values.empty() ? 0.0f : *std::max_element(grid.values.begin(), grid.values.end());
        max_spread_ = tolerance * double(grid_max);
    }

    void build(const Cell& c) {
        const CellStats s = stats(grid_, c);
        if (s.max == 0.0f) return;  // empty space costs nothing
        const long voxels = long(c.extent.x) * c.extent.y * c.extent.z;
        if (voxels == 1 || double(s.max) - double(s.min) <= max_spread_) {
            emit(c, s.sum / double(voxels), double(voxels));
            return;
        }
        // Halve the axes longer than half the longest one, so cells stay near-cubic (a sphere stands in for
        // a cube better than for a slab) and thin grids are not cut along their thin axis first.
        const int longest = std::max({c.extent.x, c.extent.y, c.extent.z});
        glm::ivec3 parts(1);
        for (int a = 0; a < 3; ++a)
            if (c.extent[a] > 1 && 2 * c.extent[a] > longest) parts[a] = 2;
        for (int pz = 0; pz < parts.z; ++pz)
            for (int py = 0; py < parts.y; ++py)
                for (int px = 0; px < parts.x; ++px) {
                    const glm::ivec3 p(px, py, pz);
                    Cell child{c.lo, c.extent};
                    for (int a = 0; a < 3; ++a)
                        if (parts[a] == 2) {
                            const int half = c.extent[a] / 2;
                            child.lo[a] = c.lo[a] + (p[a] ? half : 0);
                            child.extent[a] = p[a] ? c.extent[a] - half : half;
                        }
                    build(child);
                }
    }

    std::size_t count() const { return count_; }
    std::vector<Sphere>& spheres() { return spheres_; }

private:
    void emit(const Cell& c, double mean, double voxels) {
        ++count_;
        if (count_only_) return;
        const double volume = voxels * grid_.voxel_size * grid_.voxel_size * grid_.voxel_size;
        Sphere s;
        s.center = grid_.voxel_center(glm::dvec3(c.lo) + 0.5 * glm::dvec3(c.extent - 1));
        s.radius = std::cbrt(3.0 * volume / (4.0 * kPi));  // the cell's volume, so mass is conserved
        s.extinction = mean * options_.extinction_scale;
        s.albedo = options_.albedo;
        spheres_.push_back(s);
    }

    const DensityGrid& grid_;
    const SphereCloudOptions& options_;
    double max_spread_ = 0.0;  // the largest spread of densities a one-sphere cell may have
    bool count_only_;
    std::size_t count_ = 0;
    std::vector<Sphere> spheres_;
};

std::size_t count_spheres(const DensityGrid& grid, const SphereCloudOptions& options, double tolerance) {
    Builder b(grid, options, tolerance, /*count_only=*/true);
    b.build(Cell{glm::ivec3(0), grid.size});
    return b.count();
}

void check(const SphereCloudOptions& o) {
    if (!(o.tolerance >= 0.0 && o.tolerance <= 1.0))
        throw std::invalid_argument("tolerance must be in [0, 1] (got " + std::to_string(o.tolerance) + ")");
    if (!(std::isfinite(o.extinction_scale) && o.extinction_scale > 0.0))
        throw std::invalid_argument("extinction scale must be positive and finite (got " +
                                    std::to_string(o.extinction_scale) + ")");
    for (int a = 0; a < 3; ++a)
        if (!(o.albedo[a] >= 0.0 && o.albedo[a] <= 1.0))
            throw std::invalid_argument("albedo components must be in [0, 1] (got " + std::to_string(o.albedo[a]) + ")");
}

}  // namespace

SphereCloud grid_to_spheres(const DensityGrid& grid, const SphereCloudOptions& options) {
    check(options);
    SphereCloud cloud;
    cloud.tolerance = options.tolerance;
    if (grid.values.empty()) return cloud;
    // The count falls as the tolerance grows (a coarser tree's leaves are unions of a finer one's), and
    // tolerance 1 leaves one sphere, so bisection finds the finest tolerance that fits.
    if (options.max_spheres > 0 && count_spheres(grid, options, options.tolerance) > options.max_spheres) {
        double lo = std::max(options.tolerance, 1e-6), hi = 1.0;
        for (int step = 0; step < 30 && hi - lo > 1e-4 * hi; ++step) {
            const double mid = std::sqrt(lo * hi);  // tolerances span decades
            (count_spheres(grid, options, mid) > options.max_spheres ? lo : hi) = mid;
        }
        cloud.tolerance = hi;
    }
    Builder b(grid, options, cloud.tolerance, /*count_only=*/false);
    b.build(Cell{glm::ivec3(0), grid.size});
    cloud.spheres = std::move(b.spheres());
    return cloud;
}

}  // namespace brume
