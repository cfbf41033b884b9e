// The spheres' optical depth toward the sun, sum_k tau_k len_k(x) (render/sun_light.h), tabulated once
// per frame on a light-space lattice and read back by trilinear interpolation: trace's accurate shadow
// technique (render/fast_tracer.cpp) samples it along every view segment, where an exact lookup, a walk
// over the spheres above x, costs 10-30 times as much.
//
// The lattice: axes u, v across the sun's rays and s = dot(x, l) along them (l toward the sun), one
// spacing `cell` on all three. Each vertex holds the exact optical depth of its point, to float
// rounding (the chords are splatted in float, relative to each sphere's centre cell): a sphere adds
// tau (top - max(s, bottom)) to a column's vertices at s below the top of its chord, so a vertex value
// is exact, and between vertices the error is the interpolation's. The column margins hold 0 (outside
// every shadow cylinder) and the lowest vertex lies below every sphere, so clamping there is exact.
// Boxes are not in the map: their shadows are sharp, and the tracer takes them in closed form
// (render/sun_light.h box_shadow_interval).
//
// Nor are outsized spheres (at most kMaxOutsized, each over kOutsizedRadii times the median radius: an
// atmosphere around the scene, a fog bank around a few puffs): a lookup adds their chords in closed form
// (a square root each). In the lattice their radius set the spacing (a fraction of the mean radius)
// and their reach its extent, so that the small spheres' shadows were blurred away: three puffs inside
// a fog sphere of radius 10,000 read a mean error of 4.2e-3 of the peak (the bound: 1e-3).
//
// A scene of at most kMaxWholeSpheres (48) spheres takes every one whole the same way
// (sun_depth_map.cpp whole_spheres): its lattice holds no sphere (a handful of zeros), and its spacing,
// kWholeSpheresFiner times finer than a lattice of spheres of their lower median radius, only sets the
// pieces along the view rays. A lone sphere's blurred shadow edge, and pieces too long for the bend of
// its own depth, missed the accuracy target there, and so did half of the sparse clouds of 9-400 spheres
// that a randomised sweep tried (docs/accuracy.md, "Sparse clouds").
//
// Past that, a cloud of at most kMaxColumnSpheres (256) dense spheres (the 99th percentile of tau r at
// least 1, where the lattice keeps its spacing) is taken exactly through light-space columns (Columns:
// squares about a mean radius across, each listing the spheres whose shadow disc overlaps it, from the
// sun down): a lookup walks its column until a sphere ends below the point, adding each chord in closed
// form, and the lattice is again the least one, its spacing the whole spheres'. A lattice missed the
// target in 32 of 49 random clouds of 49-256 dense spheres, which columns meet but for one; dense smoke
// of more spheres (the presets') averages the lattice's blur away, and thin smoke hardly shows it.
//
// Coordinates are relative to an origin (the eye), so float keeps its precision where the rays are.
#pragma once

#include "render/outsized_spheres.h"
#include "render/simd8.h"
#include "render/sun_light.h"
#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace brume {

// The instructions a build's splat and sums run on: Best takes AVX-512's scatters for the splat's adds
// and AVX2 for the rest where the CPU has them, Avx2 stops at AVX2 (so that tests hold that path too
// on a CPU with AVX-512), Portable any x86-64's. The same float operations every way, so the same map
// bit for bit (tests/test_sun_depth_map.cpp). FloatSunDepth takes Avx2 as Best.
enum class MapInstructions { Best, Avx2, Portable };

class SunDepthMap {
public:
    SunDepthMap() = default;  // empty
    // Empty when the light casts no shadows or there are no spheres. At most `max_vertices` lattice
    // points (at least 32): the spacing is the larger of a fraction of the spheres' mean radius and what
    // that budget allows; where every sphere is whole (a scene of at most kMaxWholeSpheres), 18 points
    // and the spacing of kWholeSpheresFiner. `threads` as parallel_for's.
    SunDepthMap(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                std::size_t max_vertices = kDefaultMaxVertices, MapInstructions instructions = MapInstructions::Best);
    // The map of this frame, built again in place: an owner that keeps its map from frame to frame
    // (render/fast_tracer.h FastTraceScratch, the frame path's resources) reuses its memory.
    void build(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
               std::size_t max_vertices = kDefaultMaxVertices, MapInstructions instructions = MapInstructions::Best);

    // The lattice that build() would fill (its spacing, extent and outsized spheres, so its header and
    // ray()), without the vertices: for a map that the GPU fills in the frame path's light pass
    // (shaders/sun_map_build.comp, render/frame/frame_resources.h). empty() stays true (there are no
    // values here to read); planned() says whether there is a lattice to fill.
    void plan(const Scene& scene, const SunLight& sun, const glm::dvec3& origin,
              std::size_t max_vertices = kDefaultMaxVertices);
    bool planned() const { return nu_ > 0; }

    static constexpr std::size_t kDefaultMaxVertices = std::size_t(8) << 20;  // 32 MiB of floats
    // The most any budget allows: a vertex's index stays an int.
    static constexpr std::size_t kMaxVertices = std::size_t(1) << 30;

    bool empty() const { return size_ == 0; }

    // A sphere a lookup takes in closed form, in lattice units: centre, radius^2, tau * spacing.
    struct Outsized {
        float u, v, s, r2, depth_per_cell;
    };
    static constexpr int kMaxOutsized = brume::kMaxOutsized;  // render/outsized_spheres.h
    static constexpr double kOutsizedRadii = brume::kOutsizedRadii;
    // A scene of at most this many spheres with a medium has every one taken whole (outsized() lists
    // them all, and the lattice holds none); past it, the outsized ones alone (sun_depth_map.cpp
    // whole_spheres).
    static constexpr int kMaxWholeSpheres = 48;
    static_assert(kMaxWholeSpheres >= kMaxOutsized);
    // Whether a map of this scene takes every sphere whole (at most kMaxWholeSpheres with a medium),
    // holding none in its lattice.
    static bool takes_every_sphere_whole(const Scene& scene);
    // Past kMaxWholeSpheres, a cloud of at most this many spheres (besides the outsized ones) whose smoke
    // is dense (the 99th percentile of tau r at least 1) has them taken exactly through light-space
    // columns (has_columns(); sun_depth_map.cpp columns_take); the rest, and thin smoke, a lattice.
    static constexpr int kMaxColumnSpheres = 256;
    // Whether a map of this scene holds no sphere in its lattice: every one whole, or in columns.
    static bool takes_spheres_exactly(const Scene& scene);
    std::span<const Outsized> outsized() const { return {outsized_.data(), std::size_t(outsized_count_)}; }
    float cell() const { return cell_; }
    int size_u() const { return nu_; }
    int size_v() const { return nv_; }
    int size_s() const { return ns_; }

    // For the GPU's copy (shaders/shared.h SunGridHeader): the vertices, (j * nu + i) * ns + k; the
    // origin's lattice coordinates; the inverse spacing. The axes are the SunLight's grid_u, grid_v and
    // toward_sun.
    std::span<const float> values() const { return {depth_.get(), size_}; }
    glm::dvec3 origin_coordinates() const { return glm::dvec3(-u_lo_, -v_lo_, -s_lo_) / cell_d_; }
    double inverse_cell() const { return 1.0 / cell_d_; }

    // A ray origin + t d in lattice units: coordinate a = a0 + t da on each axis.
    struct Ray {
        float u0, du, v0, dv, s0, ds;
    };
    Ray ray(const glm::dvec3& d) const;

    // The interpolated optical depth at origin + t d.
    [[gnu::always_inline]] float optical_depth(const Ray& r, float t) const {
        const float gu = r.u0 + t * r.du, gv = r.v0 + t * r.dv, raw_s = r.s0 + t * r.ds;
        const float outsized = outsized_depth(gu, gv, raw_s);
        if (has_columns()) return column_depth(gu, gv, raw_s) + outsized;
        // Outside the lattice's columns (or NaN): outside every shadow cylinder in it.
        if (!(gu >= 0.0f && gv >= 0.0f && gu < last_u_ && gv < last_v_)) return outsized;
        const float gs = std::min(std::max(raw_s, 0.0f), last_s_);
        // 32-bit indices: the lattice holds at most kMaxVertices (a constructor's bound).
        const int i = int(gu), j = int(gv), k = std::min(int(gs), ns_ - 2);
        const float fu = gu - float(i), fv = gv - float(j), fs = gs - float(k);
        const float* p = depth_.get() + ((j * nu_ + i) * ns_ + k);
        const auto along_s = [fs](const float* q) { return q[0] + fs * (q[1] - q[0]); };
        const float a = along_s(p), b = along_s(p + ns_), c = along_s(p + stride_v_), e = along_s(p + stride_v_ + ns_);
        const float ab = a + fu * (b - a), ce = c + fu * (e - c);
        return (ab + fv * (ce - ab)) + outsized;
    }

    // The outsized spheres' optical depth above a point in lattice coordinates: each one's chord from
    // the point (or its bottom) to its top, as the splat takes a column's, times tau.
    float outsized_depth(float u, float v, float s) const {
        float depth = 0.0f;
        for (int k = 0; k < outsized_count_; ++k) {
            const Outsized& o = outsized_[std::size_t(k)];
            const float du = u - o.u, dv = v - o.v, h2 = o.r2 - (du * du + dv * dv);
            if (!(h2 > 0.0f)) continue;
            const float half = std::sqrt(h2), bottom = o.s - half;
            const float from = s > bottom ? s : bottom;  // NaN: from the bottom, as the lanes take it
            depth += o.depth_per_cell * std::max(o.s + half - from, 0.0f);
        }
        return depth;
    }

    // optical_depth at eight points given in lattice coordinates (a Ray's at some t), one a lane
    // (render/simd8.h): the same interpolation without a branch, its eight vertices read by `gather`,
    // a pair along s at a time (simd::GatherByLanes, or GatherAvx2 in code compiled for AVX2). A point
    // outside the columns (or NaN) reads 0, as optical_depth's. Not for an empty map.
    template <class Gather>
    [[gnu::always_inline]] simd::Float8 optical_depth8(simd::Float8 u, simd::Float8 v, simd::Float8 s,
                                                       const Gather& gather) const {
        using simd::Float8;
        using simd::Int8;
        const Float8 zero{};
        if (has_columns()) return column_depth8(u, v, s) + outsized_depth8(u, v, s);
        const Float8 raw_u = u, raw_v = v, raw_s = s;  // the outsized spheres' chords take them unclamped
        const Int8 inside = (u >= 0.0f) & (v >= 0.0f) & (u < last_u_) & (v < last_v_);
        // Outside, vertex (0, 0) is read (and its value dropped) in place of one that may not exist.
        u = inside ? u : zero;
        v = inside ? v : zero;
        s = s > 0.0f ? s : zero;  // NaN too
        s = s < last_s_ ? s : zero + last_s_;
        const Int8 i = __builtin_convertvector(u, Int8), j = __builtin_convertvector(v, Int8);
        Int8 k = __builtin_convertvector(s, Int8);
        k = k < ns_ - 2 ? k : Int8{} + (ns_ - 2);
        const Float8 fu = u - __builtin_convertvector(i, Float8), fv = v - __builtin_convertvector(j, Float8),
                     fs = s - __builtin_convertvector(k, Float8);
        const Int8 c = (j * nu_ + i) * ns_ + k;
        const float* depth = depth_.get();
        // The eight vertices: along s (+1), u (+ns) and v (+stride_v). Inlined wherever this is (a Float8
        // returned by a call crosses it differently with and without AVX: GCC's -Wpsabi).
        const auto along_s = [&](int offset) __attribute__((always_inline)) {
            Float8 lo, hi;
            gather.pair(depth, c + offset, lo, hi);
            return lo + fs * (hi - lo);
        };
        const Float8 a = along_s(0), b = along_s(ns_), e = along_s(stride_v_), f = along_s(stride_v_ + ns_);
        const Float8 ab = a + fu * (b - a), ef = e + fu * (f - e);
        const Float8 value = ab + fv * (ef - ab);
        return (inside ? value : zero) + outsized_depth8(raw_u, raw_v, raw_s);
    }

    // outsized_depth at eight points, one a lane (NaN-free where the points are).
    [[gnu::always_inline]] simd::Float8 outsized_depth8(simd::Float8 u, simd::Float8 v, simd::Float8 s) const {
        using simd::Float8;
        const Float8 zero{};
        Float8 depth{};
        for (int k = 0; k < outsized_count_; ++k) {
            const Outsized& o = outsized_[std::size_t(k)];
            const Float8 du = u - o.u, dv = v - o.v, h2 = o.r2 - (du * du + dv * dv);
            // No lane in its shadow, so it adds nothing: the square root and the rest are skipped (in a
            // scene taken whole, most spheres' shadows miss most points: trace's frame 0.65-0.85x on
            // scenes of 16-32 spheres, the same images). Culling a tile's spheres by its points' bounds
            // first gained nothing measurable (a tile's points spread across most of a small cloud's
            // shadow).
            if (simd::mask8(h2 > zero) == 0) continue;
            const Float8 half = simd::SqrtSse{}(h2 > zero ? h2 : zero);
            const Float8 bottom = o.s - half, from = s > bottom ? s : bottom, chord = (o.s + half) - from;
            depth += h2 > zero && chord > zero ? o.depth_per_cell * chord : zero;
        }
        return depth;
    }

    // A sparse cloud's spheres, exactly (has_columns()): the chords above a point in lattice coordinates
    // of the spheres its column lists, as outsized_depth takes them. 0 outside the columns (or NaN).
    float column_depth(float u, float v, float s) const {
        const float cu = (u - columns_.u0) * columns_.inverse_side, cv = (v - columns_.v0) * columns_.inverse_side;
        if (!(cu >= 0.0f && cv >= 0.0f && cu < float(columns_.nu) && cv < float(columns_.nv))) return 0.0f;
        const std::size_t cell = std::size_t(int(cv)) * std::size_t(columns_.nu) + std::size_t(int(cu));
        float depth = 0.0f;
        for (std::uint32_t n = columns_.first[cell]; n < columns_.first[cell + 1]; ++n) {
            const ColumnSphere& o = columns_.spheres[n];
            if (o.top < s) break;  // from the sun down: this one and every later one end below the point
            const float du = u - o.u, dv = v - o.v, h2 = o.r2 - (du * du + dv * dv);
            if (!(h2 > 0.0f)) continue;
            const float half = std::sqrt(h2), bottom = o.s - half;
            const float from = s > bottom ? s : bottom;
            depth += o.depth_per_cell * std::max(o.s + half - from, 0.0f);
        }
        return depth;
    }

    // column_depth at eight points, one a lane. The lanes that share a column walk its list together,
    // one sphere at a time over the eight lanes (a tile's points come a ray's pieces after another, so
    // mostly one or two columns a call), until a sphere ends below all of them.
    [[gnu::always_inline]] simd::Float8 column_depth8(simd::Float8 u, simd::Float8 v, simd::Float8 s) const {
        using simd::Float8;
        using simd::Int8;
        const Float8 zero{};
        const Float8 cu = (u - columns_.u0) * columns_.inverse_side, cv = (v - columns_.v0) * columns_.inverse_side;
        const Int8 inside = (cu >= 0.0f) & (cv >= 0.0f) & (cu < float(columns_.nu)) & (cv < float(columns_.nv));
        // Outside (or NaN), column 0 is converted (and dropped) in place of a coordinate out of int's range.
        const Float8 in_u = inside ? cu : zero, in_v = inside ? cv : zero;
        const Int8 cell = inside ? __builtin_convertvector(in_v, Int8) * columns_.nu + __builtin_convertvector(in_u, Int8)
                                 : Int8{} - 1;
        Float8 depth{};
        Int8 pending = inside;
        for (int lanes = simd::mask8(pending); lanes != 0; lanes = simd::mask8(pending)) {
            const std::int32_t c = cell[__builtin_ctz(unsigned(lanes))];
            const Int8 here = pending & (cell == c);
            pending = pending & ~here;
            float lowest = std::numeric_limits<float>::infinity();  // the lowest point of the column's lanes
            for (int l = 0; l < 8; ++l)
                if (here[l] != 0) lowest = std::min(lowest, s[l]);
            const std::uint32_t last = columns_.first[std::size_t(c) + 1];
            for (std::uint32_t n = columns_.first[std::size_t(c)]; n < last; ++n) {
                const ColumnSphere& o = columns_.spheres[n];
                if (o.top < lowest) break;  // ends below every lane's point, as does every later one
                const Float8 du = u - o.u, dv = v - o.v, h2 = o.r2 - (du * du + dv * dv);
                // A lane whose point is above the top stops here, as column_depth's walk does (its chord's
                // end, o.s + half rounded apart from top, could otherwise add an ulp that one does not).
                const Int8 hit = here & (h2 > zero) & ~(s > o.top);
                if (simd::mask8(hit) == 0) continue;
                const Float8 half = simd::SqrtSse{}(h2 > zero ? h2 : zero);
                const Float8 bottom = o.s - half, from = s > bottom ? s : bottom, chord = (o.s + half) - from;
                depth += hit && chord > zero ? o.depth_per_cell * chord : zero;
            }
        }
        return depth;
    }

    // Whether the map takes a sparse cloud's spheres exactly through light-space columns (sun_depth_map.cpp
    // columns_take) rather than in its lattice, which is then the least one of zeros.
    bool has_columns() const { return columns_.nu > 0; }
    // A sphere as a column lists it, in lattice units: centre, radius^2, tau * spacing, and its top, s + r.
    struct ColumnSphere {
        float u, v, s, r2, depth_per_cell, top;
    };
    // The columns: nu x nv squares of side 1 / inverse_side (lattice units) from (u0, v0); column
    // (i, j) lists spheres[first[j * nu + i] ... first[j * nu + i + 1]), every sphere whose shadow disc
    // overlaps it, from the sun down (by top, largest first). For the GPU's copy (shaders/shared.h
    // SunGridHeader.columns).
    struct Columns {
        float u0 = 0.0f, v0 = 0.0f, inverse_side = 0.0f;
        int nu = 0, nv = 0;
        std::vector<std::uint32_t> first;
        std::vector<ColumnSphere> spheres;
    };
    const Columns& columns() const { return columns_; }

    // optical_depth8 at n points, into out, eight at a time (0 where the map is empty). The arrays hold
    // n rounded up to a multiple of 8.
    template <class Gather>
    [[gnu::always_inline]] void optical_depths(const float* gu, const float* gv, const float* gs, float* out,
                                               std::size_t n, const Gather& gather) const {
        const std::size_t padded = (n + 7) / 8 * 8;
        if (empty()) {
            std::fill(out, out + padded, 0.0f);
            return;
        }
        for (std::size_t m = 0; m < padded; m += 8)
            simd::store8(out + m, optical_depth8(simd::load8(gu + m), simd::load8(gv + m), simd::load8(gs + m), gather));
    }

private:
    // No lattice (empty(), every lookup 0), its memory kept; also what a build that throws leaves.
    void make_empty();
    // build() (fill) and plan() (the lattice alone).
    void lay_out(const Scene& scene, const SunLight& sun, const glm::dvec3& origin, int threads,
                 std::size_t max_vertices, MapInstructions instructions, bool fill);

    glm::dvec3 u_{0.0}, v_{0.0}, l_{0.0};
    double u_lo_ = 0.0, v_lo_ = 0.0, s_lo_ = 0.0;  // the lattice's first vertex on each axis
    double cell_d_ = 1.0;
    float cell_ = 1.0f;
    int nu_ = 0, nv_ = 0, ns_ = 0;
    int stride_v_ = 0;                             // nu_ * ns_: from one row of columns to the next
    float last_u_ = 0.0f, last_v_ = 0.0f, last_s_ = 0.0f;  // nu_ - 1, nv_ - 1, ns_ - 1
    // (j * nu + i) * ns + k: vertex (u_lo + i cell, v_lo + j cell, s_lo + k cell). Not a std::vector,
    // whose resize would zero the whole map before the build writes every vertex anyway.
    std::unique_ptr<float[]> depth_;
    std::size_t size_ = 0;
    std::size_t capacity_ = 0;  // depth_'s floats, at least size_
    // A build's worker scratch for the band of rows it splats: each cell's share of the chords that end
    // in it (`ends`) and the whole-cell runs as differences (`runs`), group of eight columns by group
    // (each group's cells one after another, a cell's eight columns side by side, so that the sums
    // take eight columns as one vector and read down a group's cells in one run); for each
    // column the highest and lowest cell a chord reached (-1 and ns: none). Zeroed once, and put back
    // to zero as the sums read it, so a band costs what its spheres touch, not the band's size; kept
    // from build to build (`bottom`'s none written again when ns changes: scratch_ns_).
    struct BandScratch {
        std::vector<float> ends, runs;
        std::vector<int> top, bottom;
    };
    std::vector<BandScratch> band_scratch_;
    int scratch_ns_ = 0;
    std::array<Outsized, kMaxWholeSpheres> outsized_{};
    int outsized_count_ = 0;
    Columns columns_;  // nu = 0: none (the lattice holds the spheres, or every one is whole)
};

}  // namespace brume
