#include "render/sun_depth_map.h"

#include "render/outsized_spheres.h"
#include "render/simd8.h"
#include "sim/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace brume {
namespace {

// The lattice spacing as a fraction of the spheres' mean radius: a shadow cylinder's edge, where the
// optical depth has its steepest slope, is then resolved by a few vertices across the sphere. 0.09
// rather than 0.1: with trace's refined pieces the map's blur is what is left of plume's and
// explosion's p99.9 error (bench shadows at 128x96, pieces refined from 2 cells: 1.04e-2 and 8.7e-3
// at 0.1, 9.05e-3 and 7.5e-3 at 0.09), for 1.37x the vertices (docs/accuracy.md).
constexpr double kCellPerRadius = 0.09;
// Where the media are thin, the spacing widens, up to kThinWidenMax times: at a shadow cylinder's edge
// the map's blur misses an optical depth of about tau sqrt(2 r h) (h the spacing, the depth growing as
// the square root of the distance from the edge there), tau r sqrt(2 h / r) for a sphere whose own depth
// across is tau r. 0.09 was chosen for plume's and explosion's spheres, tau r of 1-4; a spacing of
// 0.09 / (tau r)^2 radii keeps a thinner sphere's miss at what one of tau r = 1 makes at 0.09, so the
// spacing widens by 1 / (tau r)^2 of the thickest spheres (the 99th percentile: a few outliers are not
// the scene), within [1, kThinWidenMax]. Measured (bench shadows, 128x96, trace; the same by ppll): fog
// presets, tau r at most 0.5, widened 2x, p99.9 of the peak low-sun 6.65e-3 to 6.38e-3, fog-bank
// 1.01e-3 to 1.13e-3, ground-fog 5.00e-3 to 5.77e-3, vdb-cloud 5.16e-3 to 5.23e-3, crossing 3.81e-3
// to 7.62e-3, within the 1e-2 target; their shadowed frames at 640x360 0.88-0.96x (the build's
// vertices an eighth; docs/performance.md). 4x took low-sun and ground-fog past 1.2e-2. Dense smoke
// (plume, campfire, explosion: tau r of 2-4 at the 99th percentile) keeps 0.09.
constexpr double kThinWidenMax = 2.0;
constexpr double kThickPercentile = 0.99;

// The spacing's widening for the spheres' depths across, tau r (reordered): 1 / t^2 of their
// kThickPercentile-th, t, within [1, kThinWidenMax].
double thin_media_widening(std::vector<double>& depth_across) {
    if (depth_across.empty()) return 1.0;
    const std::size_t k = std::min(depth_across.size() - 1, std::size_t(kThickPercentile * double(depth_across.size())));
    std::nth_element(depth_across.begin(), depth_across.begin() + std::ptrdiff_t(k), depth_across.end());
    const double t = depth_across[k];
    return t > 0.0 ? std::clamp(1.0 / (t * t), 1.0, kThinWidenMax) : kThinWidenMax;
}
// The spheres a lookup takes whole, as ascending indices into scene.spheres: in a scene of at most
// SunDepthMap::kMaxWholeSpheres (48) spheres with a medium, every one of them; otherwise the outsized
// ones (render/outsized_spheres.h). A lattice blurs a lone sphere's shadow edge, and the pieces it sets
// along the view rays (SUN_PIECE_CELLS cells) run too long across the bend of a sphere's own depth
// toward the sun: one sphere of radius 1 and extinction 0.65 read a mean error of 2.7e-3 of the peak
// and a p99.9 of 3.3e-2 against the reference, where the target is 1e-3 and 1e-2 (docs/accuracy.md).
// Nor does a sparse cloud's lattice average the blur away: of 72 random scenes of 9-48 spheres, 36
// missed the target, and 1 does whole (a close, dim view lit from behind). Trace's frame costs what the
// lattice's did for 9-32 spheres (a median 1.01x, up to 2.7x), and a median 1.39x, up to 2.0x, for
// 48: a lookup tests every whole sphere, and takes a square root for those whose shadow holds one of
// its eight points. At 64 a median 2.26x, and the lattice missed in 2 of 8 there: the default scene's
// 64 spheres, dense enough that the lattice meets the target (p99.9 2.9e-3), would have cost 1.8x by
// trace and 2.2-2.5x by ppll on lavapipe taken whole. Past 48 a dense cloud of at most 256 goes to the
// columns (columns_take: a lookup walks only its column's spheres), and the rest to the lattice
// (100-400 spheres taken whole cost 6-13x its frame; docs/accuracy.md, "Sparse clouds").
std::vector<std::size_t> whole_spheres(const Scene& scene) {
    if (!SunDepthMap::takes_every_sphere_whole(scene)) return outsized_spheres(scene);
    std::vector<std::size_t> all;
    for (std::size_t k = 0; k < scene.spheres.size(); ++k)
        if (scene.spheres[k].extinction > 0.0 && scene.spheres[k].radius > 0.0) all.push_back(k);
    return all;
}
// Calls each(sphere, whole) for every sphere with a medium (the others add nothing to the optical
// depth), in scene order, `whole` saying whether `whole_indices` (ascending, whole_spheres) holds it:
// the one split of the scene that the map (lay_out) and its predicate (takes_spheres_exactly) make.
template <class Each>
void split_spheres(const Scene& scene, const std::vector<std::size_t>& whole_indices, const Each& each) {
    for (std::size_t k = 0, next = 0; k < scene.spheres.size(); ++k) {
        const Sphere& sp = scene.spheres[k];
        if (!(sp.extinction > 0.0) || !(sp.radius > 0.0)) continue;
        const bool whole = next < whole_indices.size() && whole_indices[next] == k;
        next += whole ? 1 : 0;
        each(sp, whole);
    }
}
// Where every sphere is whole, the spacing that sets the pieces along the view rays (SUN_PIECE_CELLS
// cells): kCellPerRadius of the spheres' lower median radius, kWholeSpheresFiner times finer, not
// widened in thin media (no lattice blurs a shadow there; what is left is the pieces' straight line
// across the bend of a sphere's depth toward the sun). Measured on one sphere against the reference
// (trace at 64x48, mean and p99.9 of the peak; docs/accuracy.md): radius 1, extinction 0.65, no
// ambient: 4.1e-4 and 2.6e-3 at 8, 8.5e-4 and 6.4e-3 at 4 (the lattice's pieces read 2.7e-3 and
// 3.3e-2); radius 0.1 filling a 12-degree view: 6.1e-4 at extinction 50, 3.2e-3 at 1,000 and 7.2e-3
// at 10,000 at 8 (the lattice's: 1.7e-2, 0.17 and 0.20). Over 264 random scenes of at most eight
// spheres, 87 missed the target before and 2 now; trace's frame there costs a median 1.26x what it did,
// up to 16x beside spheres of extinction in the thousands. The mean radius (the lattice's rule) missed
// 6: two spheres do not tell which one is outsized, and a fog sphere set the pieces again. Over 40
// random scenes of 9-64 spheres taken whole, pieces from 1, 2, 4 and 8 times finer missed in 7, 4, 2
// and 1.
constexpr double kWholeSpheresFiner = 8.0;
// Rows of columns per work item of the build: each item splats the spheres that reach its rows.
constexpr int kBandRows = 4;
// Columns whose suffix sums are taken side by side (the build's last step).
constexpr int kColumnsAtOnce = 8;
// Where a band's local column starts in its workers' scratch: each group of kColumnsAtOnce columns
// holds its cells one after another, a cell's eight columns side by side, so that the sums read a
// group's scratch as one run down the cells (cell by cell over the whole band, a cell was a row of
// the band apart from the next, and the sums waited on those reads).
inline std::size_t scratch_column(std::size_t local_column, std::size_t cells) {
    return (local_column / kColumnsAtOnce) * cells * kColumnsAtOnce + local_column % kColumnsAtOnce;
}

struct Projected {
    double u, v, s, r, tau;
};

// A column's side: a mean radius (twice that made trace's frame 5-10% faster on three clouds, but a
// GPU invocation walks a column of its own, and a wider one lists more spheres that do not hold its
// point; half or a quarter of it, 10-40% slower), and wide enough that there are at most about
// (kColumnsPerSide sqrt(n) + 3)^2 columns for n spheres (about 1,200 for 256): an outsized sphere past
// the eight taken whole, listed in every column, then stays in proportion to the cloud.
constexpr double kColumnSideRadii = 1.0;
constexpr double kColumnsPerSide = 2.0;

// The columns of `spheres` in the lattice frame (u_lo, v_lo, s_lo, cell), into `out` (its memory
// reused): squares of kColumnSideRadii mean radii, each listing the spheres whose shadow disc overlaps
// it, grown by a sliver (a lookup projects its point in float, and one a rounding error outside a
// column must still find the discs that reach it; an extra candidate adds exactly 0), from the sun
// down. `out` has no columns (nu = 0) until they are all written, so a build that throws leaves none.
void build_columns(const std::vector<Projected>& spheres, double u_lo, double v_lo, double s_lo, double cell,
                   SunDepthMap::Columns& out) {
    using ColumnSphere = SunDepthMap::ColumnSphere;
    std::vector<ColumnSphere> lattice(spheres.size());
    double lo_u = std::numeric_limits<double>::infinity(), hi_u = -lo_u, lo_v = lo_u, hi_v = -lo_u, radius_sum = 0.0;
    for (std::size_t n = 0; n < spheres.size(); ++n) {
        const Projected& p = spheres[n];
        const double u = (p.u - u_lo) / cell, v = (p.v - v_lo) / cell, s = (p.s - s_lo) / cell, r = p.r / cell;
        lattice[n] = ColumnSphere{float(u), float(v), float(s), float(r * r), float(p.tau * cell), float(s + r)};
        lo_u = std::min(lo_u, u - r);
        hi_u = std::max(hi_u, u + r);
        lo_v = std::min(lo_v, v - r);
        hi_v = std::max(hi_v, v + r);
        radius_sum += r;
    }
    const double count = double(spheres.size());
    const double extent = std::max(hi_u - lo_u, hi_v - lo_v);
    double side = std::max(kColumnSideRadii * radius_sum / count, extent / (kColumnsPerSide * std::sqrt(count) + 1.0));
    const int nu = int(std::ceil((hi_u - lo_u) / side)) + 1, nv = int(std::ceil((hi_v - lo_v) / side)) + 1;
    // Half a column of slack before the first, so that no disc's grown square rounds out of the columns.
    const double u0 = lo_u - 0.5 * side, v0 = lo_v - 0.5 * side;
    const auto span = [&](const Projected& p, double centre, double origin, int n, int& a, int& b) {
        const double r = p.r / cell, grow = 1e-3 * side + 1e-6 * (std::abs(centre) + r);
        a = std::clamp(int(std::floor((centre - r - grow - origin) / side)), 0, n - 1);
        b = std::clamp(int(std::floor((centre + r + grow - origin) / side)), 0, n - 1);
    };
    out.nu = out.nv = 0;
    out.u0 = float(u0);
    out.v0 = float(v0);
    out.inverse_side = float(1.0 / side);
    out.first.assign(std::size_t(nu) * std::size_t(nv) + 1, 0);
    // Two passes: count, then fill in scene order; then each column's list from the sun down (by top,
    // largest first; a stable sort, so the lists do not depend on the library's).
    for (std::size_t n = 0; n < spheres.size(); ++n) {
        int i0, i1, j0, j1;
        span(spheres[n], double(lattice[n].u), u0, nu, i0, i1);
        span(spheres[n], double(lattice[n].v), v0, nv, j0, j1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) ++out.first[std::size_t(j) * std::size_t(nu) + std::size_t(i) + 1];
    }
    for (std::size_t c = 1; c < out.first.size(); ++c) out.first[c] += out.first[c - 1];
    out.spheres.resize(out.first.back());
    std::vector<std::uint32_t> next(out.first.begin(), out.first.end() - 1);
    for (std::size_t n = 0; n < spheres.size(); ++n) {
        int i0, i1, j0, j1;
        span(spheres[n], double(lattice[n].u), u0, nu, i0, i1);
        span(spheres[n], double(lattice[n].v), v0, nv, j0, j1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) out.spheres[next[std::size_t(j) * std::size_t(nu) + std::size_t(i)]++] = lattice[n];
    }
    for (std::size_t c = 0; c + 1 < out.first.size(); ++c)
        std::stable_sort(out.spheres.begin() + std::ptrdiff_t(out.first[c]), out.spheres.begin() + std::ptrdiff_t(out.first[c + 1]),
                         [](const ColumnSphere& a, const ColumnSphere& b) { return a.top > b.top; });
    out.nu = nu;
    out.nv = nv;
}

// Whether the map takes its spheres (those it neither takes whole nor leaves outsized; `depth_across`
// their tau r, reordered) exactly through columns rather than in a lattice: a cloud of at most
// SunDepthMap::kMaxColumnSpheres whose smoke is dense, where the lattice keeps its spacing
// (thin_media_widening 1: the 99th percentile of tau r at least 1).
// A lattice blurs each sphere's shadow edge over its spacing, and the pieces along a view ray run across
// the bend of each one's depth; dense smoke of many spheres averages both away (the presets meet the
// target there), and so does thin smoke, where the edge is faint. A sparse cloud of dense puffs does
// not: of 90 random clouds of 49-400 spheres (trace at 64x48 against the reference, docs/accuracy.md
// "Sparse clouds"), the lattice missed the target in 54, the columns in 2 (both dim: peaks of 0.034
// and 0.16; p99.9 3.9e-2 and 1.06e-2); of the 17 thin ones (tau r at most 0.6) the lattice met it in
// 16 (the other: mean 1.3e-3). Columns cost trace's frame a median 1.97x the lattice's on 20 clouds of
// 100-200 spheres (0.84-3.4x; 320x180, one thread), and 1.45-3.2x on the presets, where the lattice meets the target: so past
// kMaxColumnSpheres the lattice (plume's 1,150 spheres, explosion's 991-1,700, campfire's from frame
// 15 on), and the fog presets keep theirs.
// BRUME_SUN_COLUMNS=always or never overrides the rule (auto, or unset: the rule), so that a session
// with a GPU can time the columns against the lattice on the same frames (explosion's densest, where
// the lattice misses the target; docs/accuracy.md), as BRUME_SUN_MAP picks where the map is filled.
bool columns_take(std::vector<double>& depth_across) {
    if (depth_across.empty()) return false;
    if (const char* choice = std::getenv("BRUME_SUN_COLUMNS")) {
        const std::string c = choice;
        if (c == "always") return true;
        if (c == "never") return false;
        if (c != "auto") throw std::invalid_argument("BRUME_SUN_COLUMNS='" + c + "': 'auto', 'always' or 'never'");
    }
    return depth_across.size() <= std::size_t(SunDepthMap::kMaxColumnSpheres) && thin_media_widening(depth_across) == 1.0;
}


// A sphere as the splat takes it: in lattice units (cells), relative to the lattice's first vertex;
// its rows and columns; what a whole cell of its chord adds, tau * cell.
struct SplatSphere {
    double u, v, s, r2;
    int i0, i1, j0, j1;
    float depth_per_cell;
};

// Where a band's splat writes (render/sun_depth_map.h BandScratch, cell by cell).
struct SplatScratch {
    float* ends;
    float* runs;
    int* highest;  // per local column, the highest and lowest cell a chord reached
    int* lowest;
    std::size_t cells;        // per column (ns): a group of kColumnsAtOnce columns holds cells * 8 floats
    std::size_t row_columns;  // from one row of the band to the next
    int row0;                 // the band's first row
    int last_cell;            // ns - 2
};

// What a row's eight lanes of one sphere's chords add into the scratch (splat_sphere): in lane l, column
// `first + l` (a local column) when bit l of `crossed` is set; its chord's bottom and top cells; what its
// bottom and top ends add (from their cells' bounds), and the whole chord (where both ends share a
// cell); `whole` for each cell between them (+ at the top one's, - at the bottom's: `runs`).
struct ChordLanes {
    std::size_t first;
    int crossed;
    simd::Int8 bottom_cell, top_cell;
    simd::Float8 bottom_part, top_part, chord;
    float whole;
};

// The adds, a crossed lane at a time: for any x86-64 (and AVX2).
struct AddLaneByLane {
    [[gnu::always_inline]] void operator()(const ChordLanes& c, const SplatScratch& out) const {
        alignas(32) float bottom_part[8], top_part[8], chord[8];
        alignas(32) std::int32_t cell_bottom[8], cell_top[8];
        simd::store8(bottom_part, c.bottom_part);
        simd::store8(top_part, c.top_part);
        simd::store8(chord, c.chord);
        simd::store8(cell_bottom, c.bottom_cell);
        simd::store8(cell_top, c.top_cell);
        for (int crossed = c.crossed; crossed != 0; crossed &= crossed - 1) {
            const int l = std::countr_zero(unsigned(crossed));
            const std::size_t column = c.first + std::size_t(l);
            const int b = cell_bottom[l], t = cell_top[l];
            out.highest[column] = std::max(out.highest[column], t);
            out.lowest[column] = std::min(out.lowest[column], b);
            const std::size_t at = scratch_column(column, out.cells);
            float* const end_b = out.ends + (at + std::size_t(b) * kColumnsAtOnce);
            if (b == t) {
                *end_b += chord[l];
                continue;
            }
            *end_b += bottom_part[l];
            out.ends[at + std::size_t(t) * kColumnsAtOnce] += top_part[l];
            if (t - 1 > b) {  // whole cells b + 1 .. t - 1
                out.runs[at + std::size_t(t - 1) * kColumnsAtOnce] += c.whole;
                out.runs[at + std::size_t(b) * kColumnsAtOnce] -= c.whole;
            }
        }
    }
};

#if defined(__x86_64__) && defined(__GNUC__)
// The same adds, the eight lanes at once by AVX-512's scatters (AVX512F and VL, on 256-bit vectors):
// the lanes are eight different columns, so no two write one address, and each address gets the same
// float additions in the same order (sphere after sphere) as AddLaneByLane's, so the same map. The
// scratch's cells are indexed in 32 bits (the build gives a band whose scratch is larger to the AVX2
// adds).
struct AddByScatter {
    [[gnu::target("avx2,avx512f,avx512vl")]] void operator()(const ChordLanes& c, const SplatScratch& out) const {
        const __mmask8 crossed = __mmask8(c.crossed);
        const __m256i first = _mm256_set1_epi32(int(c.first));
        const __m256i column = _mm256_add_epi32(first, _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
        // Each lane's column's first cell (scratch_column), then a cell every kColumnsAtOnce floats.
        const __m256i group_floats = _mm256_set1_epi32(int(out.cells) * kColumnsAtOnce);
        const __m256i base = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(column, 3), group_floats),
                                              _mm256_and_si256(column, _mm256_set1_epi32(kColumnsAtOnce - 1)));
        const __m256i stride = _mm256_set1_epi32(kColumnsAtOnce);
        const __m256i b = __m256i(c.bottom_cell), t = __m256i(c.top_cell);
        // The highest and lowest cells: eight neighbouring columns, read and written under the mask
        // (the lanes past a band's last column are never touched).
        int* const highest = out.highest + c.first;
        int* const lowest = out.lowest + c.first;
        _mm256_mask_storeu_epi32(highest, crossed,
                                 _mm256_max_epi32(_mm256_maskz_loadu_epi32(crossed, highest), t));
        _mm256_mask_storeu_epi32(lowest, crossed, _mm256_min_epi32(_mm256_maskz_loadu_epi32(crossed, lowest), b));
        const __mmask8 one_cell = _mm256_mask_cmpeq_epi32_mask(crossed, b, t);
        const __mmask8 two_cells = crossed & __mmask8(~one_cell);
        const __mmask8 runs = _mm256_mask_cmpgt_epi32_mask(two_cells, _mm256_sub_epi32(t, _mm256_set1_epi32(1)), b);
        const __m256i at_bottom = _mm256_add_epi32(_mm256_slli_epi32(b, 3), base);
        const __m256i at_top = _mm256_add_epi32(_mm256_slli_epi32(t, 3), base);
        add(out.ends, crossed, at_bottom, _mm256_mask_blend_ps(one_cell, __m256(c.bottom_part), __m256(c.chord)));
        add(out.ends, two_cells, at_top, __m256(c.top_part));
        const __m256 whole = _mm256_set1_ps(c.whole);
        add(out.runs, runs, _mm256_sub_epi32(at_top, stride), whole);
        // runs[b] -= whole: a subtraction, as AddLaneByLane's.
        const __m256 now = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), runs, at_bottom, out.runs, 4);
        _mm256_mask_i32scatter_ps(out.runs, runs, at_bottom, _mm256_sub_ps(now, whole), 4);
    }

private:
    // base[index] += value in the lanes of `mask`.
    [[gnu::target("avx2,avx512f,avx512vl")]] static void add(float* base, __mmask8 mask, __m256i index,
                                                            __m256 value) {
        const __m256 now = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), mask, index, base, 4);
        _mm256_mask_i32scatter_ps(base, mask, index, _mm256_add_ps(now, value), 4);
    }
};
#endif

// One sphere's chords through the band's columns, eight columns of a row at a time in SIMD lanes:
// each column's chord [bottom, top] (in cells: s +- sqrt(r^2 - du^2 - dv^2)), the cells its ends lie in
// and what they add, in float, relative to the cell of the sphere's centre (so the lanes' values stay
// small and keep float's precision); then each column the chord crosses adds its share into the
// scratch (`add`: AddLaneByLane or AddByScatter). `sqrt8` as simd::SqrtSse or SqrtAvx.
template <class Sqrt, class Add>
[[gnu::always_inline]] inline void splat_sphere(const SplatSphere& p, const SplatScratch& out, const Sqrt& sqrt8,
                                                const Add& add) {
    using simd::Float8;
    using simd::Int8;
    const Float8 lane{0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};
    const int centre_cell = int(std::floor(p.s));
    const float centre = float(p.s - double(centre_cell));  // in [0, 1)
    // The chord's ends lie within r of the centre: an offset of more cells than that keeps them
    // positive, where truncation is floor.
    const int offset = int(std::ceil(std::sqrt(p.r2))) + 2;
    const Float8 zero{}, depth_per_cell = zero + p.depth_per_cell;
    const Int8 lowest_cell = Int8{} - centre_cell, highest_cell = Int8{} + (out.last_cell - centre_cell);
    for (int j = p.j0; j <= p.j1; ++j) {
        const double dv = double(j) - p.v;
        const float across = float(p.r2 - dv * dv);  // r^2 - dv^2: what is left for du^2 and the chord
        if (!(across > 0.0f)) continue;
        const std::size_t row_local = std::size_t(j - out.row0) * out.row_columns;
        for (int i = p.i0; i <= p.i1; i += 8) {
            const Float8 du = float(double(i) - p.u) + lane;
            const Float8 h2 = across - du * du;
            int crossed = simd::mask8(h2 > 0.0f) & ((1 << std::min(8, p.i1 - i + 1)) - 1);
            if (crossed == 0) continue;
            const Float8 half = sqrt8(h2 > 0.0f ? h2 : zero);
            const Float8 top = centre + half, bottom = centre - half;
            // Cells relative to the centre's, clamped to the lattice's.
            Int8 ct = __builtin_convertvector(top + float(offset), Int8) - offset;
            Int8 cb = __builtin_convertvector(bottom + float(offset), Int8) - offset;
            ct = ct < lowest_cell ? lowest_cell : ct;
            ct = ct > highest_cell ? highest_cell : ct;
            cb = cb < lowest_cell ? lowest_cell : cb;
            cb = cb > highest_cell ? highest_cell : cb;
            // What each end adds, measured from its own cell's bounds, and the whole chord where both
            // ends share a cell.
            add(ChordLanes{row_local + std::size_t(i), crossed, cb + centre_cell, ct + centre_cell,
                           depth_per_cell * (__builtin_convertvector(cb + 1, Float8) - bottom),
                           depth_per_cell * (top - __builtin_convertvector(ct, Float8)), depth_per_cell * (half + half),
                           p.depth_per_cell},
                out);
        }
    }
}

// The band's spheres, splatted: compiled for any x86-64, for AVX2, and for AVX-512 (its scatters) where
// the CPU has them: the same operations on the same floats, so the same map (8 lanes in one register
// rather than two; the adds eight at a time rather than one). Not FMA: a contracted a - b c rounds once,
// where the portable code rounds twice (AVX-512 brings FMA with it, so contraction is turned off).
[[gnu::flatten]] void splat_portable(const SplatSphere* spheres, std::size_t count, const SplatScratch& out) {
    for (std::size_t n = 0; n < count; ++n) splat_sphere(spheres[n], out, simd::SqrtSse{}, AddLaneByLane{});
}
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2"), gnu::flatten]] void splat_avx2(const SplatSphere* spheres, std::size_t count,
                                                      const SplatScratch& out) {
    for (std::size_t n = 0; n < count; ++n) splat_sphere(spheres[n], out, simd::SqrtAvx{}, AddLaneByLane{});
}
[[gnu::target("avx2,avx512f,avx512vl"), gnu::optimize("fp-contract=off"), gnu::flatten]] void splat_avx512(
    const SplatSphere* spheres, std::size_t count, const SplatScratch& out) {
    for (std::size_t n = 0; n < count; ++n) splat_sphere(spheres[n], out, simd::SqrtAvx{}, AddByScatter{});
}
#endif

// A band's sums (render/sun_depth_map.h BandScratch): the map's vertices of rows [row0, row1), the
// scratch they are summed from, and the lattice's shape.
struct BandSums {
    float* depth;
    float* ends;
    float* runs;
    int* highest;  // per local column, as SplatScratch's
    int* lowest;
    std::size_t band_columns, row_columns;
    int row0, row1, nu, ns;
};

// Every vertex of the band's rows, written once: 0 above a column's highest chord (and in a column no
// chord reached), then the suffix sums from there down, a group of kColumnsAtOnce columns at a time
// in SIMD lanes: each column's sum is one chain of dependent additions, and the group's cells lie
// side by side in the scratch (the same sums in the same order, lane by lane: the values do not
// depend on how the columns are grouped).
[[gnu::always_inline]] inline void sum_band(const BandSums& b) {
    const std::size_t column = std::size_t(b.ns);
    for (int j = b.row0; j < b.row1; ++j)
        for (int i = 0; i < b.nu; i += kColumnsAtOnce) {
            const int group = std::min(kColumnsAtOnce, b.nu - i);
            const std::size_t first_local = std::size_t(j - b.row0) * b.row_columns + std::size_t(i);
            const std::size_t group_scratch = scratch_column(first_local, std::size_t(b.ns));
            int highest = -1, lowest = b.ns;
            for (int c = 0; c < group; ++c) {
                const std::size_t local_column = first_local + std::size_t(c);
                highest = std::max(highest, b.highest[local_column]);
                lowest = std::min(lowest, b.lowest[local_column]);
                b.highest[local_column] = -1;
                b.lowest[local_column] = b.ns;
            }
            float* out[kColumnsAtOnce];
            for (int c = 0; c < group; ++c) {
                out[c] = b.depth + (std::size_t(j) * std::size_t(b.nu) + std::size_t(i + c)) * column;
                std::fill(out[c] + (highest + 1), out[c] + b.ns, 0.0f);  // above the group's highest chord
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
                float* const run = b.runs + (group_scratch + std::size_t(k) * kColumnsAtOnce);
                float* const end = b.ends + (group_scratch + std::size_t(k) * kColumnsAtOnce);
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
}

// sum_band for any x86-64, and for AVX2 where the CPU has it, as the splat is: the same additions in
// double and the same roundings to float, so the same map (PortableInstructionsBuildTheSameMap). In
// AVX2 the four sums of four doubles stay in registers; compiled for SSE they went through the stack
// at every cell, and the sums were 41% of explosion's build at one thread (perf). The build, one
// thread, alone: explosion 0.77x, vdb-cloud 0.82x (docs/performance.md).
[[gnu::flatten]] void sum_band_portable(const BandSums& b) { sum_band(b); }
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2"), gnu::flatten]] void sum_band_avx2(const BandSums& b) { sum_band(b); }
#endif

}  // namespace

SunDepthMap::SunDepthMap(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                         std::size_t max_vertices, MapInstructions instructions) {
    build(scene, sun, origin, threads, max_vertices, instructions);
}

void SunDepthMap::plan(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, std::size_t max_vertices) {
    lay_out(scene, sun, origin, 0, max_vertices, MapInstructions::Best, false);
}

void SunDepthMap::build(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                        std::size_t max_vertices, MapInstructions instructions) {
    lay_out(scene, sun, origin, threads, max_vertices, instructions, true);
}

bool SunDepthMap::takes_spheres_exactly(const Scene& scene) {
    if (takes_every_sphere_whole(scene)) return true;
    std::vector<double> depth_across;  // of the spheres lay_out would hold in a lattice or columns
    split_spheres(scene, whole_spheres(scene), [&](const Sphere& sp, bool whole) {
        if (!whole) depth_across.push_back(sp.extinction * sp.radius);
    });
    return columns_take(depth_across);
}

bool SunDepthMap::takes_every_sphere_whole(const Scene& scene) {
    std::size_t with_medium = 0;
    for (const Sphere& sp : scene.spheres) with_medium += sp.extinction > 0.0 && sp.radius > 0.0 ? 1 : 0;
    return with_medium <= std::size_t(kMaxWholeSpheres);
}

void SunDepthMap::lay_out(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                          std::size_t max_vertices, MapInstructions instructions, bool fill) {
    make_empty();  // until the lattice is known; the vertices' memory and the workers' scratch stay
    if (!sun.shadows() || scene.spheres.empty()) return;
    // At least the least lattice a finite spacing gives, 4 x 4 x 2 vertices (a column of margin on
    // each side of at least one cell): below it the spacing search never ended (under 18), or ended at
    // an infinite spacing whose lookups were NaN and read no shadow (18-31).
    max_vertices = std::clamp(max_vertices, std::size_t(32), kMaxVertices);
    u_ = sun.grid_u();
    v_ = sun.grid_v();
    l_ = sun.toward_sun();
    // The lattice's spheres, and apart from them the ones a lookup takes whole, in closed form
    // (whole_spheres: the outsized ones, or every one of a few), in scene order.
    std::vector<Projected> spheres, outsized;
    spheres.reserve(scene.spheres.size());
    split_spheres(scene, whole_spheres(scene), [&](const Sphere& sp, bool whole) {
        const glm::dvec3 c = sp.center - origin;
        const Projected p{glm::dot(c, u_), glm::dot(c, v_), glm::dot(c, l_), sp.radius, sp.extinction};
        (whole ? outsized : spheres).push_back(p);
    });
    if (spheres.empty() && outsized.empty()) return;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    // The lattice's shape and frame (u_lo, v_lo: its first vertex; s_lo: its lowest), and the whole
    // spheres in its units.
    const auto set_lattice = [&](int nu, int nv, int ns, double cell, double u_lo, double v_lo, double s_lo) {
        nu_ = nu;
        nv_ = nv;
        ns_ = ns;
        stride_v_ = nu * ns;
        last_u_ = float(nu - 1);
        last_v_ = float(nv - 1);
        last_s_ = float(ns - 1);
        cell_d_ = cell;
        cell_ = float(cell);
        u_lo_ = u_lo;
        v_lo_ = v_lo;
        s_lo_ = s_lo;
        for (const Projected& p : outsized) {
            const double r = p.r / cell;
            outsized_[std::size_t(outsized_count_++)] = Outsized{float((p.u - u_lo_) / cell), float((p.v - v_lo_) / cell),
                                                                 float((p.s - s_lo_) / cell), float(r * r),
                                                                 float(p.tau * cell)};
        }
    };
    // Room for the vertices. The last build's memory is reused where it is large enough: freed and
    // allocated again, its pages went back to the system and faulted in afresh on the next frame's
    // first touch (plume at 640x360, one thread: 6% of the frame in page faults under the build's
    // writes). A map that outgrows its memory takes a quarter more room, within the budget: in
    // playback the lattice grows with the smoke, frame after frame (ground-fog, frames 40-69: 6.62 M to
    // 7.47 M vertices, a new largest every second frame), and a map allocated to the vertex each time
    // took 41-47 ms to build against 3 ms in its kept memory (ground-fog in the preview window rendered
    // at half the speed of the same frame alone). A first build takes what it needs: a map built once
    // (one frame without a kept scratch) gains nothing from room, and at 32 MiB its block would leave
    // glibc's heap for pages of its own.
    const auto reserve_vertices = [&](std::size_t vertex_count) {
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
    };
    // Where every sphere is taken exactly (whole, or through columns): no sphere in the lattice, which is
    // the least one (3 x 3 x 2 vertices of 0) for lookups to read, its spacing kWholeSpheresFiner's of
    // the lower median radius of `sized` (the spheres that are not outsized), which sets the pieces.
    // Framed at the origin (the eye), not at the spheres' reach: the lookups' float coordinates are
    // then as large as the distance from the eye, not as an atmosphere's radius (framed at a fog
    // of radius 1e7, two puffs' shadows read p99.9 5.9e-2 of the peak against 2.3e-3).
    // Not below 1e-12 of the spheres' reach from the eye: the lookups' coordinates, in cells, and
    // their squares stay within float's range (a sphere of radius 1e-18 beside one of 0.5 set a
    // spacing of 1e-20, and every accurate frame was NaN).
    const auto exact_spacing = [&](const std::vector<Projected>& sized) {
        std::vector<double> radii;
        double reach = 0.0;
        for (const Projected& p : sized) radii.push_back(p.r);
        for (const std::vector<Projected>* set : {&spheres, &outsized})
            for (const Projected& p : *set)
                reach = std::max(reach, std::max({std::abs(p.u), std::abs(p.v), std::abs(p.s)}) + p.r);
        const std::size_t middle = (radii.size() - 1) / 2;  // the lower median: of two, the smaller
        std::nth_element(radii.begin(), radii.begin() + std::ptrdiff_t(middle), radii.end());
        return std::max(kCellPerRadius * radii[middle] / kWholeSpheresFiner, 1e-12 * reach);
    };
    const auto least_lattice = [&](double cell) {
        set_lattice(3, 3, 2, cell, -cell, -cell, 0.0);
        if (!fill) return;
        reserve_vertices(18);
        std::fill(depth_.get(), depth_.get() + 18, 0.0f);
    };
    if (spheres.empty()) {
        least_lattice(exact_spacing(outsized));  // every sphere whole (whole_spheres)
        return;
    }
    std::vector<double> depth_across;  // tau r of each
    depth_across.reserve(spheres.size());
    for (const Projected& p : spheres) depth_across.push_back(p.tau * p.r);
    if (columns_take(depth_across)) {
        // A cloud of dense spheres, not too many: each one exactly, through the columns (columns_take).
        const double cell = exact_spacing(spheres);
        build_columns(spheres, -cell, -cell, 0.0, cell, columns_);
        least_lattice(cell);
        return;
    }
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf, s_lo = kInf, s_hi = -kInf, radius_sum = 0.0;
    for (const Projected& p : spheres) {
        u_lo = std::min(u_lo, p.u - p.r);
        u_hi = std::max(u_hi, p.u + p.r);
        v_lo = std::min(v_lo, p.v - p.r);
        v_hi = std::max(v_hi, p.v + p.r);
        s_lo = std::min(s_lo, p.s - p.r);
        s_hi = std::max(s_hi, p.s + p.r);
        radius_sum += p.r;
    }

    // The spacing: a fraction of the mean radius, wider in thin media (thin_media_widening), widened
    // until the lattice fits the budget. One empty
    // column beyond the discs on each side of u and v (value 0, so lookups outside need no test but
    // the lattice's bounds); along s, the first vertex at the lowest sphere's bottom (below it the
    // optical depth is the whole column's) and the last at or above the highest sphere's top (0).
    double cell = kCellPerRadius * radius_sum / double(spheres.size()) * thin_media_widening(depth_across);
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
    set_lattice(nu, nv, ns, cell, u_lo - cell, v_lo - cell, s_lo);
    if (!fill) return;  // plan(): the lattice without its vertices (empty(), planned())
    // Left unwritten here: each band writes every vertex of its rows exactly once (below), so a frame
    // pays one streaming pass over the map, in parallel, not a zeroing pass before it.
    reserve_vertices(std::size_t(nu) * std::size_t(nv) * std::size_t(ns));

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
    // The workers' scratch is laid out group by group (scratch_column): a group of kColumnsAtOnce
    // columns holds cell k of its eight columns side by side, cell after cell, each row of columns
    // padded to whole groups, so that the sums below take a group's eight columns as one vector and
    // read its cells as one run. Explosion's build at one thread took 0.90-0.95x of its time with the
    // cells a band's width apart (plume 0.97-0.99x); the same map.
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
    // Each worker's spheres of the band it splats (SplatSphere), reused from band to band.
    std::vector<std::vector<SplatSphere>> worker_spheres(workers);
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
        // The band's spheres in lattice units, clipped to its rows, then splatted.
        std::vector<SplatSphere>& band_spheres = worker_spheres[std::size_t(worker)];
        band_spheres.clear();
        const double inverse_cell = 1.0 / cell;
        for (std::uint32_t n = band_first[band]; n < band_first[band + 1]; ++n) {
            const Projected& p = spheres[band_items[n]];
            int j0, j1;
            row_range(p, j0, j1);
            const double r = p.r * inverse_cell;
            band_spheres.push_back(SplatSphere{
                (p.u - u_lo_) * inverse_cell, (p.v - v_lo_) * inverse_cell, (p.s - s_lo_) * inverse_cell, r * r,
                std::clamp(int(std::ceil((p.u - p.r - u_lo_) / cell)), 0, nu - 1),
                std::clamp(int(std::floor((p.u + p.r - u_lo_) / cell)), 0, nu - 1), std::max(j0, row0),
                std::min(j1, row1 - 1), float(p.tau * cell)});
        }
        const SplatScratch target{w.ends.data(), w.runs.data(), w.top.data(), w.bottom.data(), column,
                                  row_columns, row0, ns - 2};
#if defined(__x86_64__) && defined(__GNUC__)
        if (instructions == MapInstructions::Best && simd::cpu_has_avx512vl() &&
            band_columns * column <= std::size_t(std::numeric_limits<std::int32_t>::max())) {
            splat_avx512(band_spheres.data(), band_spheres.size(), target);
        } else if (instructions != MapInstructions::Portable && simd::cpu_has_avx2()) {
            splat_avx2(band_spheres.data(), band_spheres.size(), target);
        } else {
            splat_portable(band_spheres.data(), band_spheres.size(), target);
        }
#else
        (void)instructions;
        splat_portable(band_spheres.data(), band_spheres.size(), target);
#endif
        const BandSums sums{depth_.get(), w.ends.data(), w.runs.data(), w.top.data(), w.bottom.data(), band_columns,
                            row_columns, row0, row1, nu, ns};
#if defined(__x86_64__) && defined(__GNUC__)
        if (instructions != MapInstructions::Portable && simd::cpu_has_avx2()) {
            sum_band_avx2(sums);
            return;
        }
#endif
        sum_band_portable(sums);
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
    columns_.nu = columns_.nv = 0;  // its lists' memory kept
    outsized_count_ = 0;
    last_u_ = last_v_ = last_s_ = 0.0f;  // a lookup answers 0: no column holds it
    size_ = 0;
}

SunDepthMap::Ray SunDepthMap::ray(const glm::dvec3& d) const {
    const double inv = 1.0 / cell_d_;
    return Ray{float(-u_lo_ * inv), float(glm::dot(d, u_) * inv), float(-v_lo_ * inv),
               float(glm::dot(d, v_) * inv), float(-s_lo_ * inv), float(glm::dot(d, l_) * inv)};
}

}  // namespace brume
