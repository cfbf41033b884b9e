#include "sim/vdb/particle_splat.h"

#include "sim/scene_file.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/vdb_file.h"

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace brume {
namespace {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

bool has_mass(const Sphere& s) { return s.radius > 0.0 && s.extinction > 0.0; }

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void validate(const std::vector<Sphere>& spheres, const SplatOptions& o) {
    if (!std::isfinite(o.voxel_size) || o.voxel_size < 0.0)
        throw std::invalid_argument("voxel size must be positive and finite (got " + number(o.voxel_size) + ")");
    if (o.voxel_size == 0.0 && o.resolution < kMinSplatResolution)
        throw std::invalid_argument("resolution must be at least " + std::to_string(kMinSplatResolution) + " voxels (got " +
                                    std::to_string(o.resolution) + ")");
    if (!std::isfinite(o.extinction_scale) || !(o.extinction_scale > 0.0))
        throw std::invalid_argument("extinction scale must be positive and finite (got " + number(o.extinction_scale) + ")");
    if (o.grid_name.empty()) throw std::invalid_argument("the grid needs a name");
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const Sphere& s = spheres[i];
        const std::string at = "sphere[" + std::to_string(i) + "]";
        if (!finite(s.center)) throw std::invalid_argument(at + ".center must be finite");
        if (!std::isfinite(s.radius) || s.radius < 0.0)
            throw std::invalid_argument(at + ".radius must be finite and >= 0 (got " + number(s.radius) + ")");
        if (!std::isfinite(s.extinction) || s.extinction < 0.0)
            throw std::invalid_argument(at + ".extinction must be finite and >= 0 (got " + number(s.extinction) + ")");
        if (!finite(s.albedo) || s.albedo.x < 0.0 || s.albedo.y < 0.0 || s.albedo.z < 0.0)
            throw std::invalid_argument(at + ".albedo must be finite and >= 0");
    }
}

// A sphere in index space (voxel i centred on i) and the voxels it can deposit into, inclusive. Both
// passes over the spheres (the grid's extent, then the deposits) compute it here, so the footprints the
// extent was made from are exactly the ones deposited into.
struct Footprint {
    glm::dvec3 g{0.0};  // centre
    double r = 0.0;     // radius, in voxels
    bool trilinear = false;
    glm::dvec3 lo{0.0}, hi{0.0};  // integral values
};

Footprint footprint(const Sphere& s, const glm::dvec3& origin, double voxel) {
    Footprint f;
    f.g = (s.center - origin) / voxel;
    f.r = s.radius / voxel;
    f.trilinear = f.r < 0.5;  // under a voxel across: coverage would snap it to the voxel it sits in
    if (f.trilinear) {
        f.lo = glm::floor(f.g);
        f.hi = f.lo + 1.0;
    } else {
        // Voxel i spans [i - 0.5, i + 0.5).
        f.lo = glm::floor(f.g - f.r + 0.5);
        f.hi = glm::floor(f.g + f.r + 0.5);
    }
    return f;
}

struct Extent {
    glm::dvec3 lo{HUGE_VAL}, hi{-HUGE_VAL};
};

Extent extent(const std::vector<Sphere>& spheres, const glm::dvec3& origin, double voxel) {
    Extent e;
    for (const Sphere& s : spheres) {
        if (!has_mass(s)) continue;
        const Footprint f = footprint(s, origin, voxel);
        e.lo = glm::min(e.lo, f.lo);
        e.hi = glm::max(e.hi, f.hi);
    }
    return e;
}

// Subsamples per voxel side across y and z: 4 resolves a sphere of a few voxels well (its shares only
// shape the edge, the rescale fixes the mass); smaller spheres get more so their few voxels are still fair.
int subsamples(double r) { return std::clamp(int(std::ceil(8.0 / r)), 4, 16); }

// Calls deposit(i, j, k, share) for every voxel of the sphere's footprint it overlaps, with share its
// overlap volume in voxels (summed over the calls for one voxel: exactly 1 wholly inside), and returns the
// sum of the shares. deposit may be null: the sum alone, the first pass of the rescale.
template <typename Deposit>
double cover(const Footprint& f, Deposit&& deposit) {
    constexpr bool sum_only = std::is_same_v<std::decay_t<Deposit>, std::nullptr_t>;
    const int n = subsamples(f.r);
    const double weight = 1.0 / (double(n) * double(n));  // each column's cross-section, in voxel faces
    const double r2 = f.r * f.r;
    double total = 0.0;
    std::array<glm::dvec2, 16 * 16> chords;  // of one row of voxels: [x0, x1] of each column meeting the sphere
    for (double k = f.lo.z; k <= f.hi.z; k += 1.0)
        for (double j = f.lo.y; j <= f.hi.y; j += 1.0) {
            int m = 0;
            double inner0 = -HUGE_VAL, inner1 = HUGE_VAL;  // where every column is inside
            for (int b = 0; b < n; ++b) {
                const double dz = k - 0.5 + (b + 0.5) / n - f.g.z;
                for (int a = 0; a < n; ++a) {
                    const double dy = j - 0.5 + (a + 0.5) / n - f.g.y;
                    const double h2 = r2 - dy * dy - dz * dz;
                    if (h2 <= 0.0) continue;
                    // The column meets the sphere over [x0, x1]: exact along x.
                    const double h = std::sqrt(h2);
                    if constexpr (sum_only) {
                        total += 2.0 * h * weight;
                    } else {
                        chords[m++] = {f.g.x - h, f.g.x + h};
                        inner0 = std::max(inner0, f.g.x - h);
                        inner1 = std::min(inner1, f.g.x + h);
                    }
                }
            }
            if constexpr (!sum_only) {
                // Voxels within every column's chord are wholly inside: share 1 at once, not n^2 pieces of it.
                // Big spheres are mostly such voxels.
                const bool full = m == n * n && std::ceil(inner0 + 0.5) <= std::floor(inner1 - 0.5);
                const double full_first = full ? std::ceil(inner0 + 0.5) : 0.0;
                const double full_last = full ? std::floor(inner1 - 0.5) : -1.0;
                for (double i = full_first; i <= full_last; i += 1.0) {
                    total += 1.0;
                    deposit(i, j, k, 1.0);
                }
                for (int c = 0; c < m; ++c) {
                    const double x0 = chords[c].x, x1 = chords[c].y;
                    auto partial = [&](double first, double last) {
                        for (double i = first; i <= last; i += 1.0) {
                            const double len = std::min(i + 0.5, x1) - std::max(i - 0.5, x0);
                            if (len <= 0.0) continue;
                            total += len * weight;
                            deposit(i, j, k, len * weight);
                        }
                    };
                    const double first = std::max(f.lo.x, std::floor(x0 + 0.5));
                    const double last = std::min(f.hi.x, std::floor(x1 + 0.5));
                    if (full) {
                        partial(first, full_first - 1.0);
                        partial(full_last + 1.0, last);
                    } else {
                        partial(first, last);
                    }
                }
            }
        }
    return total;
}

std::string too_many_voxels(const glm::dvec3& size, double voxel) {
    const double count = size.x * size.y * size.z;
    // The voxel size at which the count fits, with a little room for the footprints' rounding.
    const double fits = voxel * std::cbrt(count / double(kMaxSplatVoxels)) * 1.05;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the density grid would have %.0f x %.0f x %.0f = %.0f voxels at voxel size %.6g, more than "
                  "%llu (2^30): use a larger voxel size (about %.3g or more) or a lower resolution",
                  size.x, size.y, size.z, count, voxel, static_cast<unsigned long long>(kMaxSplatVoxels), fits);
    return buf;
}

}  // namespace

SplatGrids splat_spheres(const std::vector<Sphere>& spheres, const SplatOptions& options) {
    validate(spheres, options);
    SplatGrids out;
    glm::dvec3 box_lo{HUGE_VAL}, box_hi{-HUGE_VAL};
    for (const Sphere& s : spheres) {
        if (!has_mass(s)) continue;
        ++out.spheres;
        box_lo = glm::min(box_lo, s.center - s.radius);
        box_hi = glm::max(box_hi, s.center + s.radius);
    }
    if (out.spheres == 0)
        throw std::invalid_argument(spheres.empty() ? "no spheres to make a density grid of"
                                                    : "no sphere has both a radius and an extinction above 0: "
                                                      "nothing to make a density grid of");
    const glm::dvec3 box = box_hi - box_lo;
    double voxel = options.voxel_size > 0.0 ? options.voxel_size
                                                   : std::max({box.x, box.y, box.z}) / options.resolution;
    if (!(voxel > 0.0) || !std::isfinite(voxel))
        throw std::invalid_argument("voxel size " + number(voxel) + " is not usable for these spheres");
    glm::dvec3 origin{0.0};
    Extent e;
    glm::dvec3 dims;
    // A lattice anchored at the origin rarely starts where the box does, so B / resolution voxels
    // cover resolution + 1 cells: widen the voxel until the longest side holds `resolution` at most
    // (a box straddling a lattice line of the origin keeps 2, however wide the voxel).
    for (int attempt = 0;; ++attempt) {
        origin = glm::dvec3(0.0);
        e = extent(spheres, origin, voxel);
        const double index_limit = double(1 << 30);  // OpenVDB's coordinates are int32; keep well inside
        if (glm::any(glm::greaterThan(glm::max(glm::abs(e.lo), glm::abs(e.hi)), glm::dvec3(index_limit)))) {
            origin = box_lo;  // far from the world origin at this voxel size: index from the spheres instead
            e = extent(spheres, origin, voxel);
        }
        dims = e.hi - e.lo + 1.0;
        const double longest = std::max({dims.x, dims.y, dims.z});
        if (options.voxel_size > 0.0 || longest <= options.resolution || attempt == 16) break;
        voxel *= std::max(longest / options.resolution, 1.0 + 1e-9);
    }
    // The range vdb-import reads back (sim/vdb/vdb_file.h), on the voxel as widened: a file Brume itself
    // would refuse is no export.
    if (voxel < kMinVoxelSize || voxel > kMaxCoordinate)
        throw std::invalid_argument("voxel size " + number(voxel) + " is outside [" + number(kMinVoxelSize) + ", " +
                                    number(kMaxCoordinate) + "] scene units");
    if (dims.x * dims.y * dims.z > double(kMaxSplatVoxels)) throw std::invalid_argument(too_many_voxels(dims, voxel));

    DensityGrid& grid = out.density;
    grid.name = options.grid_name;
    grid.origin = origin;
    grid.voxel_size = voxel;
    grid.min = glm::ivec3(e.lo);
    grid.size = glm::ivec3(dims);
    const std::size_t count = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
    std::vector<double> density(count, 0.0);
    std::vector<double> albedo_weighted(options.albedo_grid ? count : 0, 0.0);
    auto index = [&](double i, double j, double k) {
        return grid.offset(int(i - e.lo.x), int(j - e.lo.y), int(k - e.lo.z));
    };

    for (const Sphere& s : spheres) {
        if (!has_mass(s)) continue;
        out.sphere_mass += s.extinction * 4.0 / 3.0 * std::numbers::pi * s.radius * s.radius * s.radius;
        const Footprint f = footprint(s, origin, voxel);
        // Its mass in density * voxel volumes.
        const double mass = s.extinction / options.extinction_scale * 4.0 / 3.0 * std::numbers::pi * f.r * f.r * f.r;
        const double grey = (s.albedo.x + s.albedo.y + s.albedo.z) / 3.0;
        auto add = [&](double i, double j, double k, double amount) {
            const std::size_t at = index(i, j, k);
            density[at] += amount;
            if (options.albedo_grid) albedo_weighted[at] += amount * grey;
        };
        if (!f.trilinear) {
            // Not 0: a radius of half a voxel or more always holds a column (they are 1/4 voxel apart at most).
            const double per_share = mass / cover(f, nullptr);
            cover(f, [&](double i, double j, double k, double share) { add(i, j, k, share * per_share); });
        } else {
            // The hat functions of the 8 voxel centres around it sum to 1, so the field integrates to `mass`.
            const glm::dvec3 t = f.g - f.lo;
            for (int dk = 0; dk < 2; ++dk)
                for (int dj = 0; dj < 2; ++dj)
                    for (int di = 0; di < 2; ++di) {
                        const double w = (di ? t.x : 1.0 - t.x) * (dj ? t.y : 1.0 - t.y) * (dk ? t.z : 1.0 - t.z);
                        if (w > 0.0) add(f.lo.x + di, f.lo.y + dj, f.lo.z + dk, mass * w);
                    }
        }
    }

    // To float, carrying each voxel's rounding on to the next non-zero voxel: a uniform interior would
    // otherwise round the same way everywhere and the sum drift by up to 3e-8. The smallest voxel goes last,
    // so what is left over is under half its float spacing, the finest there is.
    grid.values.assign(count, 0.0f);
    std::size_t smallest = count;
    for (std::size_t at = 0; at < count; ++at)
        if (density[at] > 0.0 && (smallest == count || density[at] < density[smallest])) smallest = at;
    double carry = 0.0;
    auto round = [&](std::size_t at) {
        const double want = density[at] + carry;
        if (want > double(FLT_MAX))
            throw std::invalid_argument("density " + number(want) +
                                        " does not fit a float grid: use a larger extinction scale");
        const float v = want > 0.0 ? float(want) : 0.0f;
        carry = want - double(v);
        grid.values[at] = v;
    };
    for (std::size_t at = 0; at < count; ++at)
        if (density[at] != 0.0 && at != smallest) round(at);
    if (smallest < count) round(smallest);
    for (const float v : grid.values) grid.active_voxels += v != 0.0f;
    // Voxels far larger than the spheres thin their density below the smallest float: refuse a grid that
    // lost its density (or part of it) rather than write an empty or lighter one.
    const double kept = grid.mass() * options.extinction_scale;
    if (grid.active_voxels == 0 || !(std::abs(kept - out.sphere_mass) <= 1e-6 * out.sphere_mass))
        throw std::invalid_argument("at voxel size " + number(voxel) + " the spheres' density (mass " +
                                    number(out.sphere_mass) + ") does not survive as floats (the grid keeps " +
                                    number(kept) + "): use a smaller voxel size or extinction scale");

    if (options.albedo_grid) {
        DensityGrid& a = out.albedo;
        a.name = "albedo";
        a.origin = grid.origin;
        a.voxel_size = grid.voxel_size;
        a.min = grid.min;
        a.size = grid.size;
        a.values.assign(count, 0.0f);
        for (std::size_t at = 0; at < count; ++at) {
            if (grid.values[at] == 0.0f) continue;
            a.values[at] = float(albedo_weighted[at] / density[at]);
            if (a.values[at] != 0.0f) ++a.active_voxels;
        }
    }
    return out;
}

DensityGrid spheres_to_density_grid(const std::vector<Sphere>& spheres, const SplatOptions& options) {
    SplatOptions o = options;
    o.albedo_grid = false;
    return std::move(splat_spheres(spheres, o).density);
}

}  // namespace brume
