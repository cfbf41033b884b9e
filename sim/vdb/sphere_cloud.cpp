#include "sim/vdb/sphere_cloud.h"

#include "sim/scene_file.h"
#include "sim/vdb/sphere_lattice.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <map>
#include <optional>
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

float grid_max(const DensityGrid& grid) {
    return grid.values.empty() ? 0.0f : *std::max_element(grid.values.begin(), grid.values.end());
}

// Walks the octree, making a sphere of each cell whose spread is within the threshold (or of a voxel).
class Builder {
public:
    Builder(const DensityGrid& grid, const SphereCloudOptions& options, double split_threshold, bool count_only)
        : grid_(grid), options_(options), count_only_(count_only), max_spread_(split_threshold * double(grid_max(grid))) {}

    void build(const Cell& c) {
        const CellStats s = stats(grid_, c);
        if (s.max == 0.0f) return;  // empty space costs nothing
        const long voxels = long(c.extent.x) * c.extent.y * c.extent.z;
        const int longest = std::max({c.extent.x, c.extent.y, c.extent.z});
        const bool small_enough = options_.max_cell_voxels <= 0 || longest <= options_.max_cell_voxels;
        if (voxels == 1 || (small_enough && double(s.max) - double(s.min) <= max_spread_)) {
            emit(c, s.sum, double(voxels));
            return;
        }
        // Halve the axes longer than half the longest one, so cells stay near-cubic (a sphere stands in for
        // a cube better than for a slab) and thin grids are not cut along their thin axis first.
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
    void emit(const Cell& c, double density_sum, double voxels) {
        ++count_;
        if (count_only_) return;
        const double volume = voxels * grid_.voxel_size * grid_.voxel_size * grid_.voxel_size;
        const double scale = options_.sphere_scale;
        Sphere s;
        s.center = grid_.voxel_center(glm::dvec3(c.lo) + 0.5 * glm::dvec3(c.extent - 1));
        s.radius = scale * std::cbrt(3.0 * volume / (4.0 * kPi));
        // The cell's mass spread over the larger sphere: mean density / scale^3.
        s.extinction = density_sum / voxels * options_.extinction_scale / (scale * scale * scale);
        s.albedo = options_.albedo * albedo_factor(c, density_sum);
        spheres_.push_back(s);
    }

    // The albedo grid's density-weighted mean over the cell's voxel centres.
    double albedo_factor(const Cell& c, double density_sum) const {
        if (!options_.albedo_grid || density_sum <= 0.0) return 1.0;
        double weighted = 0.0;
        for (int k = c.lo.z; k < c.lo.z + c.extent.z; ++k)
            for (int j = c.lo.y; j < c.lo.y + c.extent.y; ++j)
                for (int i = c.lo.x; i < c.lo.x + c.extent.x; ++i)
                    if (const float d = grid_.at(i, j, k); d > 0.0f)
                        weighted += double(d) * options_.albedo_grid->sample(grid_.voxel_center(glm::dvec3(i, j, k)));
        return std::clamp(weighted / density_sum, 0.0, 1.0);
    }

    const DensityGrid& grid_;
    const SphereCloudOptions& options_;
    bool count_only_;
    double max_spread_;  // the largest spread of densities a one-sphere cell may have
    std::size_t count_ = 0;
    std::vector<Sphere> spheres_;
};

std::size_t count_spheres(const DensityGrid& grid, const SphereCloudOptions& options, double threshold) {
    Builder b(grid, options, threshold, /*count_only=*/true);
    b.build(Cell{glm::ivec3(0), grid.size});
    return b.count();
}

void check(const SphereCloudOptions& o) {
    using toml_text::shortest;
    if (o.max_spheres == 0 && !(o.tolerance > 0.0 && o.tolerance <= 1.0))
        throw std::invalid_argument("tolerance must be in (0, 1] (got " + shortest(o.tolerance) + ")");
    if (!(std::isfinite(o.extinction_scale) && o.extinction_scale > 0.0))
        throw std::invalid_argument("extinction scale must be positive and finite (got " + shortest(o.extinction_scale) + ")");
    for (int a = 0; a < 3; ++a)
        if (!(o.albedo[a] >= 0.0 && o.albedo[a] <= 1.0))
            throw std::invalid_argument("albedo components must be in [0, 1] (got " + shortest(o.albedo[a]) + ")");
    if (!(o.sphere_scale >= kMinSphereScale && o.sphere_scale <= kMaxSphereScale))
        throw std::invalid_argument("sphere scale must be in [" + shortest(kMinSphereScale) + ", " +
                                    shortest(kMaxSphereScale) + "] (got " + shortest(o.sphere_scale) + ")");
    if (o.axis_view_resolution < 8 || o.axis_view_resolution > 4096)
        throw std::invalid_argument("axis view resolution must be in [8, 4096] (got " + std::to_string(o.axis_view_resolution) + ")");
}

std::string percent(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g%%", 100.0 * x);
    return text;
}

// The three axis views and the caller's.
std::vector<Camera> conversion_views(const DensityGrid& grid, const SphereCloudOptions& o) {
    std::vector<Camera> views = grid_axis_views(grid, o.axis_view_resolution);
    views.insert(views.end(), o.views.begin(), o.views.end());
    return views;
}

// The cell-size caps tried, finest first: 1 is one sphere per voxel; 0 is no cap.
constexpr int kCellCaps[] = {1, 2, 4, 8, 16, 32, 0};

struct Candidate {
    int cap = 1;
    double threshold = 0.0;
    double lattice_spacing = 0.0;  // > 0: a resampled lattice (sphere_lattice.h) instead of the octree
    std::size_t spheres = 0;
    OpticalDepthError error;
    bool measured = true;
};

// Clouds at octree thresholds under one cell-size cap, each measured once. A cloud of at least `bound`
// spheres cannot beat the best found so far, so it is built but not measured (measuring is the expensive
// part); for the search it counts as passing, which steers toward coarser thresholds and fewer spheres.
class ThresholdSearch {
public:
    ThresholdSearch(const DensityGrid& grid, const SphereCloudOptions& options, int cap, const OpticalDepthViews& views,
                    std::size_t bound)
        : grid_(grid), options_(options), views_(views), bound_(bound) {
        options_.max_cell_voxels = cap;
    }

    const Candidate& at(double threshold) {
        auto it = trials_.find(threshold);
        if (it == trials_.end()) {
            // Building the cloud costs about what counting it does; measuring it is what the bound saves.
            const std::vector<Sphere> spheres = grid_to_spheres_at(grid_, options_, threshold);
            Candidate c{options_.max_cell_voxels, threshold, 0.0, spheres.size(), {}, false};
            if (c.spheres < bound_) {
                c.error = views_.measure(spheres);
                c.measured = true;
                ++measured_;
            }
            it = trials_.emplace(threshold, c).first;
        }
        return it->second;
    }
    bool meets(double threshold) {
        const Candidate& c = at(threshold);
        return !c.measured || c.error.relative_rms <= options_.tolerance;
    }
    bool fails(double threshold) { return !meets(threshold); }
    int measured() const { return measured_; }

    // The coarsest threshold that measures within tolerance. Threshold 1 is a regular lattice of cap-sized
    // cells, seam-free and the fewest spheres this cap allows, so it is tried first. Otherwise, when threshold
    // 0 passes: coarser thresholds make fewer spheres and (mostly) larger errors, so step by factors of 4
    // from the tolerance itself (a spread of t costs an error of order t) to bracket the boundary, then bisect
    // in log space. The error is not strictly monotone, so the answer is the best cloud measured, never an
    // unmeasured one.
    std::optional<Candidate> coarsest_passing() {
        constexpr double kFinest = 1e-4;  // below this, the next step is threshold 0
        if (!at(1.0).measured) return std::nullopt;  // even the fewest spheres under this cap are too many
        if (meets(1.0)) return at(1.0);
        if (fails(0.0)) return std::nullopt;
        double pass = 0.0, fail = -1.0;
        double t = std::clamp(options_.tolerance, kFinest, 1.0);
        if (meets(t)) {
            pass = t;
            while (pass < 1.0) {
                t = std::min(1.0, pass * 4.0);
                if (fails(t)) {
                    fail = t;
                    break;
                }
                pass = t;
            }
        } else {
            fail = t;
            while (fail > kFinest) {
                t = std::max(kFinest, fail / 4.0);
                if (meets(t)) {
                    pass = t;
                    break;
                }
                fail = t;
            }
        }
        if (fail > 0.0 && pass > 0.0)
            for (int step = 0; step < 5 && fail / pass > 1.15; ++step) {
                const double mid = std::sqrt(pass * fail);
                (meets(mid) ? pass : fail) = mid;
            }
        std::optional<Candidate> best;
        for (const auto& [threshold, trial] : trials_)
            if (trial.measured && trial.error.relative_rms <= options_.tolerance && (!best || trial.spheres <= best->spheres))
                best = trial;
        return best;
    }

    // Both the cap's lattice (threshold 1) and its finest tree (threshold 0) were measured and failed: larger
    // caps are coarser lattices with larger seams, so there is no point going on.
    bool failed_outright() {
        return trials_.count(1.0) && trials_.count(0.0) && at(1.0).measured && at(0.0).measured && fails(1.0) && fails(0.0);
    }

private:
    const DensityGrid& grid_;
    SphereCloudOptions options_;
    const OpticalDepthViews& views_;
    std::size_t bound_;
    int measured_ = 0;
    std::map<double, Candidate> trials_;
};

// Lattices coarser than one voxel: the error grows with the spacing (a coarser lattice is a blurrier copy of
// the field), so step up by factors of 1.5 from 1.5 voxels until one fails, then bisect between the last
// that passed and the first that failed.
std::optional<Candidate> coarsest_passing_lattice(const DensityGrid& grid, const SphereCloudOptions& options,
                                                  const OpticalDepthViews& views, int& tried) {
    const double largest = double(std::max({grid.size.x, grid.size.y, grid.size.z})) + 1.0;
    const auto trial = [&](double spacing) {
        const std::vector<Sphere> spheres = grid_to_lattice_spheres(grid, options, spacing);
        ++tried;
        return Candidate{0, 0.0, spacing, spheres.size(), views.measure(spheres)};
    };
    std::optional<Candidate> pass;
    double fail = 0.0;
    for (double spacing = 1.5; spacing <= largest; spacing *= 1.5) {
        const Candidate c = trial(spacing);
        if (c.error.relative_rms > options.tolerance) {
            fail = spacing;
            break;
        }
        pass = c;
    }
    if (!pass) return std::nullopt;
    for (int step = 0; step < 4 && fail > 0.0; ++step) {
        const double mid = std::sqrt(pass->lattice_spacing * fail);
        const Candidate c = trial(mid);
        if (c.error.relative_rms <= options.tolerance) {
            if (c.spheres <= pass->spheres) pass = c;
            else break;  // not monotone here: keep the cloud already measured
        } else {
            fail = mid;
        }
    }
    return pass;
}

// The finest lattice of at most max_spheres spheres (the count falls as the spacing grows).
std::optional<double> lattice_spacing_for_count(const DensityGrid& grid, const SphereCloudOptions& options) {
    const double largest = double(std::max({grid.size.x, grid.size.y, grid.size.z})) + 1.0;
    double lo = 1.0, hi = 1.5;
    while (grid_to_lattice_spheres(grid, options, hi).size() > options.max_spheres) {
        lo = hi;
        hi *= 1.5;
        if (hi > 2.0 * largest) return std::nullopt;
    }
    for (int step = 0; step < 12 && hi / lo > 1.01; ++step) {
        const double mid = std::sqrt(lo * hi);
        if (mid <= 1.0) break;
        (grid_to_lattice_spheres(grid, options, mid).size() > options.max_spheres ? lo : hi) = mid;
    }
    return hi;
}

// The finest threshold whose count fits under a cap (the count never rises with the threshold: a coarser
// tree's leaves are unions of a finer one's, and threshold 1 leaves one cell per cap-sized block).
std::optional<double> threshold_for_count(const DensityGrid& grid, SphereCloudOptions options, int cap) {
    options.max_cell_voxels = cap;
    if (count_spheres(grid, options, 0.0) <= options.max_spheres) return 0.0;
    if (count_spheres(grid, options, 1.0) > options.max_spheres) return std::nullopt;
    double lo = 1e-6, hi = 1.0;
    if (count_spheres(grid, options, lo) <= options.max_spheres) return lo;
    for (int step = 0; step < 30 && hi / lo > 1.0 + 1e-3; ++step) {
        const double mid = std::sqrt(lo * hi);  // thresholds span decades
        (count_spheres(grid, options, mid) > options.max_spheres ? lo : hi) = mid;
    }
    return hi;
}

}  // namespace

ToleranceUnreachable::ToleranceUnreachable(double tolerance, std::size_t finest_spheres, double finest_error)
    : std::runtime_error("tolerance " + percent(tolerance) + " cannot be met: even one sphere per voxel (" +
                         std::to_string(finest_spheres) + " spheres) measures " + percent(finest_error) +
                         " RMS optical-depth error (features a few voxels thin blur); raise the tolerance"),
      finest_error_(finest_error) {}

double spheres_extinction_mass(const std::vector<Sphere>& spheres) {
    double m = 0.0;
    for (const Sphere& s : spheres) m += s.extinction * 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
    return m;
}

std::vector<Sphere> grid_to_spheres_at(const DensityGrid& grid, const SphereCloudOptions& options, double threshold) {
    check(options);
    if (grid.values.empty()) return {};
    Builder b(grid, options, threshold, /*count_only=*/false);
    b.build(Cell{glm::ivec3(0), grid.size});
    return std::move(b.spheres());
}

SphereCloud grid_to_spheres(const DensityGrid& grid, const SphereCloudOptions& options) {
    check(options);
    SphereCloud cloud;
    if (grid.values.empty() || grid_max(grid) == 0.0f) return cloud;
    const OpticalDepthViews views(grid, options.extinction_scale, conversion_views(grid, options), options.threads);
    std::optional<Candidate> best;
    if (options.max_spheres > 0) {
        // The most accurate of the finest fitting clouds under each cap.
        for (const int cap : kCellCaps) {
            const std::optional<double> threshold = threshold_for_count(grid, options, cap);
            if (!threshold) continue;
            SphereCloudOptions capped = options;
            capped.max_cell_voxels = cap;
            const std::vector<Sphere> spheres = grid_to_spheres_at(grid, capped, *threshold);
            const Candidate c{cap, *threshold, 0.0, spheres.size(), views.measure(spheres)};
            ++cloud.clouds_tried;
            if (!best || c.error.relative_rms < best->error.relative_rms) best = c;
        }
        if (const std::optional<double> spacing = lattice_spacing_for_count(grid, options)) {
            const std::vector<Sphere> spheres = grid_to_lattice_spheres(grid, options, *spacing);
            const Candidate c{0, 0.0, *spacing, spheres.size(), views.measure(spheres)};
            ++cloud.clouds_tried;
            if (!best || c.error.relative_rms < best->error.relative_rms) best = c;
        }
    } else {
        // Resampled lattices first: seam-free at any spacing, they usually need the fewest spheres, and their
        // count bounds what the octree must beat (clouds with more spheres go unmeasured).
        best = coarsest_passing_lattice(grid, options, views, cloud.clouds_tried);
        // Octree cells: larger cells save spheres where the density is near-uniform, but where a large cell
        // meets small ones their overlapping spheres over- and under-fill (the lattice ripple cancels only
        // between equal neighbours), so each cap is searched and the fewest spheres within tolerance win.
        for (const int cap : kCellCaps) {
            ThresholdSearch search(grid, options, cap, views, best ? best->spheres : SIZE_MAX);
            const std::optional<Candidate> c = search.coarsest_passing();
            cloud.clouds_tried += search.measured();
            if (c && (!best || c->spheres < best->spheres)) best = c;
            if (!c && search.failed_outright()) break;
        }
        if (!best) {
            SphereCloudOptions voxels = options;
            voxels.max_cell_voxels = 1;
            const std::vector<Sphere> finest = grid_to_spheres_at(grid, voxels, 0.0);
            throw ToleranceUnreachable(options.tolerance, finest.size(), views.measure(finest).relative_rms);
        }
    }
    if (best->lattice_spacing > 0.0) {
        cloud.spheres = grid_to_lattice_spheres(grid, options, best->lattice_spacing);
    } else {
        SphereCloudOptions chosen = options;
        chosen.max_cell_voxels = best->cap;
        cloud.spheres = grid_to_spheres_at(grid, chosen, best->threshold);
    }
    cloud.error = best->error;
    cloud.split_threshold = best->threshold;
    cloud.max_cell_voxels = best->cap;
    cloud.lattice_spacing = best->lattice_spacing;
    return cloud;
}

}  // namespace brume
