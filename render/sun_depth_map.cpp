#include "render/sun_depth_map.h"

#include "render/simd8.h"
#include "sim/parallel_for.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace brume {
namespace {

// The lattice spacing as a fraction of the spheres' mean radius: a shadow cylinder's edge, where the
// optical depth has its steepest slope, is then resolved by a few vertices across the sphere. 0.09
// rather than 0.1: with trace's refined pieces the map's blur is what is left of plume's and
// explosion's p99.9 error (bench shadows at 128x96, pieces refined from 2 cells: 1.04e-2 and 8.7e-3
// at 0.1, 9.05e-3 and 7.5e-3 at 0.09), for 1.37x the vertices (docs/accuracy.md).
constexpr double kCellPerRadius = 0.09;
// Rows of columns per work item of the build: each item splats the spheres that reach its rows.
constexpr int kBandRows = 4;
// Columns whose suffix sums are taken side by side (the build's last step).
constexpr int kColumnsAtOnce = 8;

struct Projected {
    double u, v, s, r, tau;
};

}  // namespace

SunDepthMap::SunDepthMap(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                         std::size_t max_vertices) {
    build(scene, sun, origin, threads, max_vertices);
}

void SunDepthMap::build(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                        std::size_t max_vertices) {
    make_empty();  // until the lattice is known; the vertices' memory and the workers' scratch stay
    if (!sun.shadows() || scene.spheres.empty()) return;
    max_vertices = std::min(max_vertices, kMaxVertices);
    u_ = sun.grid_u();
    v_ = sun.grid_v();
    l_ = sun.toward_sun();
    std::vector<Projected> spheres;
    spheres.reserve(scene.spheres.size());
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf, s_lo = kInf, s_hi = -kInf, radius_sum = 0.0;
    for (const Sphere& sp : scene.spheres) {
        if (!(sp.extinction > 0.0) || !(sp.radius > 0.0)) continue;  // adds nothing to the optical depth
        const glm::dvec3 c = sp.center - origin;
        const Projected p{glm::dot(c, u_), glm::dot(c, v_), glm::dot(c, l_), sp.radius, sp.extinction};
        u_lo = std::min(u_lo, p.u - p.r);
        u_hi = std::max(u_hi, p.u + p.r);
        v_lo = std::min(v_lo, p.v - p.r);
        v_hi = std::max(v_hi, p.v + p.r);
        s_lo = std::min(s_lo, p.s - p.r);
        s_hi = std::max(s_hi, p.s + p.r);
        radius_sum += p.r;
        spheres.push_back(p);
    }
    if (spheres.empty()) return;

    // The spacing: a fraction of the mean radius, widened until the lattice fits the budget. One empty
    // column beyond the discs on each side of u and v (value 0, so lookups outside need no test but
    // the lattice's bounds); along s, the first vertex at the lowest sphere's bottom (below it the
    // optical depth is the whole column's) and the last at or above the highest sphere's top (0).
    double cell = kCellPerRadius * radius_sum / double(spheres.size());
    const auto counts = [&](double h, int& nu, int& nv, int& ns) {
        nu = int(std::ceil((u_hi - u_lo) / h)) + 3;
        nv = int(std::ceil((v_hi - v_lo) / h)) + 3;
        ns = std::max(int(std::ceil((s_hi - s_lo) / h)) + 1, 2);
    };
    int nu = 0, nv = 0, ns = 0;
    for (;;) {
        // Counts in double first: a tiny cell over a wide scene must not overflow int.
        const double du = (u_hi - u_lo) / cell + 3.0, dv = (v_hi - v_lo) / cell + 3.0, ds = (s_hi - s_lo) / cell + 2.0;
        if (du * dv * ds <= double(max_vertices)) {
            counts(cell, nu, nv, ns);
            if (std::size_t(nu) * std::size_t(nv) * std::size_t(ns) <= max_vertices) break;
        }
        cell *= 1.125;
    }
    nu_ = nu;
    nv_ = nv;
    ns_ = ns;
    stride_v_ = nu * ns;
    last_u_ = float(nu - 1);
    last_v_ = float(nv - 1);
    last_s_ = float(ns - 1);
    cell_d_ = cell;
    cell_ = float(cell);
    u_lo_ = u_lo - cell;
    v_lo_ = v_lo - cell;
    s_lo_ = s_lo;
    const std::size_t vertex_count = std::size_t(nu) * std::size_t(nv) * std::size_t(ns);
    // Left unwritten here: each band writes every vertex of its rows exactly once (below), so a frame
    // pays one streaming pass over the map, in parallel, not a zeroing pass before it. The last build's
    // memory is reused where it is large enough: freed and allocated again, its pages went back to the
    // system and faulted in afresh on the next frame's first touch (plume at 640x360, one thread: 6%
    // of the frame in page faults under the build's writes). A map that outgrows its memory takes a
    // quarter more room, within the budget: in playback the lattice grows with the smoke, frame after
    // frame (ground-fog, frames 40-69: 6.62 M to 7.47 M vertices, a new largest every second frame),
    // and a map allocated to the vertex each time took 41-47 ms to build against 3 ms in its kept
    // memory (ground-fog in the preview window rendered at half the speed of the same frame alone). A
    // first build takes what it needs: a map built once (one frame without a kept scratch) gains
    // nothing from room, and at 32 MiB its block would leave glibc's heap for pages of its own.
    if (vertex_count > capacity_) {
        const bool grows = capacity_ > 0;
        depth_.reset();  // the old one first: both at once could exceed what the machine has
        capacity_ = 0;
        const std::size_t room = grows ? std::min(max_vertices, vertex_count + vertex_count / 4) : vertex_count;
        try {
            depth_.reset(new float[room]);
        } catch (...) {
            make_empty();
            throw;
        }
        capacity_ = room;
    }
    size_ = vertex_count;

    // Each band of rows lists the spheres whose disc reaches it, in scene order (two counting passes),
    // so that bands are splatted in parallel without sharing a vertex, and the sums' order is fixed:
    // the map is the same for any thread count.
    const int bands = (nv + kBandRows - 1) / kBandRows;
    const auto row_range = [&](const Projected& p, int& j0, int& j1) {
        j0 = std::clamp(int(std::ceil((p.v - p.r - v_lo_) / cell)), 0, nv - 1);
        j1 = std::clamp(int(std::floor((p.v + p.r - v_lo_) / cell)), 0, nv - 1);
    };
    std::vector<std::uint32_t> band_first(std::size_t(bands) + 1, 0);
    for (const Projected& p : spheres) {
        int j0, j1;
        row_range(p, j0, j1);
        if (j1 < j0) continue;
        for (int b = j0 / kBandRows; b <= j1 / kBandRows; ++b) ++band_first[std::size_t(b) + 1];
    }
    for (int b = 0; b < bands; ++b) band_first[std::size_t(b) + 1] += band_first[std::size_t(b)];
    std::vector<std::uint32_t> band_items(band_first.back());
    {
        std::vector<std::uint32_t> next(band_first.begin(), band_first.end() - 1);
        for (std::size_t n = 0; n < spheres.size(); ++n) {
            int j0, j1;
            row_range(spheres[n], j0, j1);
            if (j1 < j0) continue;
            for (int b = j0 / kBandRows; b <= j1 / kBandRows; ++b)
                band_items[next[std::size_t(b)]++] = std::uint32_t(n);
        }
    }

    const std::size_t column = std::size_t(ns);
    // The workers' scratch is laid out cell by cell: cell k of every column of the band side by side
    // (k * band_columns + local column), each row of columns padded to whole groups of
    // kColumnsAtOnce, so that the sums below take a group's eight columns as one vector.
    const std::size_t row_columns = (std::size_t(nu) + kColumnsAtOnce - 1) / kColumnsAtOnce * kColumnsAtOnce;
    const std::size_t band_columns = std::size_t(kBandRows) * row_columns;
    // The workers' scratch (BandScratch), kept from the last build: a build leaves it all zero, every
    // column "none", which holds for any shape of the columns but for `bottom`'s none (ns), put right
    // when ns changes. It grows where this shape needs more (in playback the shape changes nearly
    // every frame).
    const std::size_t workers = std::size_t(worker_count(threads, std::size_t(bands)));
    if (band_scratch_.size() < workers) band_scratch_.resize(workers);
    if (scratch_ns_ != ns) {
        for (BandScratch& w : band_scratch_) std::fill(w.bottom.begin(), w.bottom.end(), ns);
        scratch_ns_ = ns;
    }
    std::vector<BandScratch>& scratch = band_scratch_;
    // Each column's u and each cell's floor s, as the splat's arithmetic takes them (u_lo + i cell,
    // s_lo + k cell), once: a load where each column took a conversion, a product and a sum three times.
    column_u_.resize(std::size_t(nu));
    for (int i = 0; i < nu; ++i) column_u_[std::size_t(i)] = u_lo_ + double(i) * cell;
    cell_floor_.resize(std::size_t(ns));
    for (int k = 0; k < ns; ++k) cell_floor_[std::size_t(k)] = s_lo_ + double(k) * cell;
    const auto splat_and_sum = [&](std::size_t band, int worker) {
        // A vertex's depth is the sum over the lattice cells above it of each cell's share of the chords:
        // depth(k) = sum over cells c >= k of inc(c), cell c = [s_c, s_c+1], inc(c) = sum tau |cell ∩ chord|.
        // A chord adds tau * cell to every cell it covers whole, and a fraction to the one or two cells
        // its ends lie in: the whole cells go in as a difference (`runs`: +tau cell at the run's top cell,
        // -tau cell below its bottom cell), the end cells into `ends`, so each column a sphere crosses
        // costs O(1), not O(chord). Two suffix sums per column, in double, then give the depths.
        BandScratch& w = scratch[std::size_t(worker)];
        if (w.ends.size() < band_columns * column) {
            w.ends.resize(band_columns * column, 0.0f);
            w.runs.resize(band_columns * column, 0.0f);
        }
        if (w.top.size() < band_columns) {
            w.top.resize(band_columns, -1);
            w.bottom.resize(band_columns, ns);
        }
        const int row0 = int(band) * kBandRows, row1 = std::min(row0 + kBandRows, nv);
        // What the loops below read, as locals: through the captures, the compiler read each again after
        // every store into the scratch, which it could not prove did not alias them.
        const double first_s = s_lo_, first_u = u_lo_, first_v = v_lo_, inverse_cell = 1.0 / cell;
        const double last_cell = double(ns - 2);  // cells 0 .. ns - 2 lie between the ns vertices
        const std::size_t stride = band_columns;
        float* const ends = w.ends.data();
        float* const runs = w.runs.data();
        int* const highest_cell = w.top.data();
        int* const lowest_cell = w.bottom.data();
        // The cell an end lies in; by the inverse spacing (a product, not a quotient: two per column). An
        // end on a cell's boundary may land in either neighbour, which changes no sum: the fraction
        // added below is measured from the cell's own bounds. Clamped first (max and min, not branches),
        // then truncated: within [0, last_cell] truncation is floor, without a libm call.
        const auto cell_of = [=](double s) { return int(std::min(std::max(0.0, (s - first_s) * inverse_cell), last_cell)); };
        const double* const column_u = column_u_.data();
        const double* const cell_floor = cell_floor_.data();
        for (std::uint32_t n = band_first[band]; n < band_first[band + 1]; ++n) {
            const Projected& p = spheres[band_items[n]];
            int j0, j1;
            row_range(p, j0, j1);
            j0 = std::max(j0, row0);
            j1 = std::min(j1, row1 - 1);
            const int i0 = std::clamp(int(std::ceil((p.u - p.r - first_u) / cell)), 0, nu - 1);
            const int i1 = std::clamp(int(std::floor((p.u + p.r - first_u) / cell)), 0, nu - 1);
            const double r2 = p.r * p.r, pu = p.u, ps = p.s, tau = p.tau;
            const float whole_cell = float(tau * cell);
            for (int j = j0; j <= j1; ++j) {
                const double dv = first_v + double(j) * cell - p.v;
                const std::size_t row_local = std::size_t(j - row0) * row_columns;
                for (int i = i0; i <= i1; ++i) {
                    const double du = column_u[i] - pu;
                    const double h2 = r2 - (du * du + dv * dv);
                    if (!(h2 > 0.0)) continue;
                    const double half = std::sqrt(h2);
                    const double top = ps + half, bottom = ps - half;
                    const std::size_t local_column = row_local + std::size_t(i);
                    const int cb = cell_of(bottom), ct = cell_of(top);
                    highest_cell[local_column] = std::max(highest_cell[local_column], ct);
                    lowest_cell[local_column] = std::min(lowest_cell[local_column], cb);
                    float* const end_b = ends + (std::size_t(cb) * stride + local_column);
                    if (cb == ct) {
                        *end_b += float(tau * (top - bottom));
                        continue;
                    }
                    *end_b += float(tau * (cell_floor[cb + 1] - bottom));
                    ends[std::size_t(ct) * stride + local_column] += float(tau * (top - cell_floor[ct]));
                    if (ct - 1 > cb) {  // whole cells cb + 1 .. ct - 1
                        runs[std::size_t(ct - 1) * stride + local_column] += whole_cell;
                        runs[std::size_t(cb) * stride + local_column] -= whole_cell;
                    }
                }
            }
        }
        // Every vertex of the band's rows, written once: 0 above a column's highest chord (and in a
        // column no chord reached), then the suffix sums from there down, a group of kColumnsAtOnce
        // columns at a time in SIMD lanes: each column's sum is one chain of dependent additions, and
        // the group's cells lie side by side in the scratch (the same sums in the same order, lane by
        // lane: the values do not depend on how the columns are grouped).
        for (int j = row0; j < row1; ++j)
            for (int i = 0; i < nu; i += kColumnsAtOnce) {
                const int group = std::min(kColumnsAtOnce, nu - i);
                const std::size_t first_local = std::size_t(j - row0) * row_columns + std::size_t(i);
                int highest = -1, lowest = ns;
                for (int c = 0; c < group; ++c) {
                    const std::size_t local_column = first_local + std::size_t(c);
                    highest = std::max(highest, w.top[local_column]);
                    lowest = std::min(lowest, w.bottom[local_column]);
                    w.top[local_column] = -1;
                    w.bottom[local_column] = ns;
                }
                float* out[kColumnsAtOnce];
                for (int c = 0; c < group; ++c) {
                    out[c] = depth_.get() + (std::size_t(j) * std::size_t(nu) + std::size_t(i + c)) * column;
                    std::fill(out[c] + (highest + 1), out[c] + ns, 0.0f);  // above the group's highest chord
                }
                if (highest < 0) continue;  // no chord in the group: every vertex 0
                // Down from the group's highest chord to its lowest: a column whose own chords end
                // lower (or that has none) adds zeros (its scratch is 0 there) and writes the 0 its
                // vertices hold, without a branch. Below every chord's bottom cell nothing ends and
                // every run has closed, so a column's depth is its whole column's: stored, not summed
                // (summing on would add, cell after cell, what float rounding left of the runs'
                // cancellation where two chords shared a cell: about 1e-7 of a chord each; the
                // presets' images came out the same).
                simd::Double4 whole_lo{}, whole_hi{}, depth_lo{}, depth_hi{};
                for (int k = highest; k >= lowest; --k) {
                    float* const run = runs + (std::size_t(k) * band_columns + first_local);
                    float* const end = ends + (std::size_t(k) * band_columns + first_local);
                    const simd::Float8 r = simd::load8(run), e = simd::load8(end);
                    whole_lo += simd::low_half(r);
                    whole_hi += simd::high_half(r);
                    depth_lo += simd::low_half(e) + whole_lo;
                    depth_hi += simd::high_half(e) + whole_hi;
                    simd::store8(run, simd::Float8{});
                    simd::store8(end, simd::Float8{});
                    const simd::Float8 depth = simd::to_float8(depth_lo, depth_hi);
                    for (int c = 0; c < group; ++c) out[c][k] = depth[c];
                }
                const simd::Float8 total = simd::to_float8(depth_lo, depth_hi);
                for (int c = 0; c < group; ++c) std::fill(out[c], out[c] + lowest, total[c]);
            }
    };
    try {
        parallel_for(std::size_t(bands), threads, splat_and_sum);
    } catch (...) {
        band_scratch_.clear();  // a band cut short left its scratch unzeroed
        make_empty();
        throw;
    }
}

void SunDepthMap::make_empty() {
    nu_ = nv_ = ns_ = 0;
    last_u_ = last_v_ = last_s_ = 0.0f;  // a lookup answers 0: no column holds it
    size_ = 0;
}

SunDepthMap::Ray SunDepthMap::ray(const glm::dvec3& d) const {
    const double inv = 1.0 / cell_d_;
    return Ray{float(-u_lo_ * inv), float(glm::dot(d, u_) * inv), float(-v_lo_ * inv),
               float(glm::dot(d, v_) * inv), float(-s_lo_ * inv), float(glm::dot(d, l_) * inv)};
}

}  // namespace brume
