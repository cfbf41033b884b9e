// The accurate shadow technique's sun light on a CPU (trace, render/fast_tracer.cpp): how long a lit
// piece of a view segment may be, the tile's pieces written down as jobs (SunJobs), and their integrals
// (resolve), each over a piece whose optical depth toward the sun is read from the light-space map
// (render/sun_depth_map.h) at its ends and taken as linear between them, halved where it changes fast
// (refine_pieces). The walks cut the pieces (FastTracer::add_sun_pieces for one ray, lit_steps_light for a
// packet row); what is here carries nothing from one piece to the next, so it runs over SIMD lanes.
// The GPU takes the same pieces with the same tests (sun_segment_integral, shaders/exact_integrator.glsl).
//
// Included by render/fast_tracer.cpp, where its functions are inlined into the tracer's tile loop
// (compiled once for any x86-64 and once for AVX2), and by tests/test_sun_jobs.cpp.
#pragma once

#include "render/simd8.h"
#include "render/simd8_math.h"
#include "render/sun_depth_map.h"
#include "shaders/shared.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace brume::sun_jobs {

using glm::dvec3;
using simd::Double4;
using simd::Float4;
using simd::Float8;
using simd::Int8;
using simd::exp_minus8;
using simd::linear_exponent_integral8;
using simd::load8;

// The longest piece, in map cells, over which the accurate technique takes the optical depth toward the
// sun as linear, before refine_pieces halves it where the depth changes fast. A lit piece is halved, up to
// kSunPieceSplits times (down to a quarter cell), while the light it may carry times its change of
// optical depth toward the sun exceeds kSunPieceDepthChange: the depth bends most where it changes
// fast, at the edges of shadow cylinders (a square-root kink), and there a linear depth over 2 cells
// was half of plume's and explosion's p99.9 error. Measured with bench shadows (docs/accuracy.md):
// 2-cell pieces, unrefined: p99.9 at 128x96 plume 1.44e-2, explosion 1.20e-2; halving every piece
// (1 cell) doubles the lookups and leaves plume at 1.10e-2; refined from 2 cells (3 splits) 9.05e-3
// and 7.53e-3 (with the 0.09 map); refined from 4 cells (4 splits) 9.01e-3 and 7.61e-3 for 10-33%
// fewer lookups than that (low-sun, fog-bank: long smooth fog); from 8 cells explosion rises to 8.8e-3
// and low-sun's 2.3e-3 to 3.9e-3.
// The light a piece may carry is its view transmittance times the sun integrand at its start, times the
// share of that light the piece's own media scatter: 1 - exp(-sigma_t len) at most, taken as
// min(1, sigma_t len / kSunPieceThinDepth). Without that share, thin fog's pieces were halved for a change
// of depth that they hardly light (fog-bank frame 56 at 640x360: 573 k halvings, 37 k with it; ground-fog
// 422 k to 157 k), and a tenth of fog-bank's frame went into halving them; with a share of sigma_t len
// itself (kSunPieceThinDepth 1), plume's p99.9 at 128x96 rose from 9.01e-3 to 1.02e-2, at 0.25 to 9.36e-3
// (docs/accuracy.md).
// In thin media a piece may run longer, up to kSunPieceThinWiden times kSunPieceCells, while its own
// optical depth sigma_t len stays within kSunPieceThinDepth: below that its media scatter a share of the
// light in proportion to their depth, so what a linear depth across it misses shrinks with sigma_t too,
// and the halving test still sees the change of depth across the whole piece. Long smooth fog is cut
// into fewer pieces, each a map read and two exponentials: at 640x360, one thread, low-sun's shadowed
// frame took 0.87-0.92x as long; fog-bank's 0.95-1.0x; plume's and explosion's pieces (sigma_t 3-5 per
// unit) are untouched, their images the same. p99.9 at 128x96 (bench shadows, docs/accuracy.md) rose
// within the 1e-2 bound where the media are thin: low-sun 2.25e-3 to 6.65e-3, vdb-cloud 2.33e-3 to
// 5.16e-3, crossing 1.74e-3 to 3.81e-3, fog-bank 5.0e-4 to 1.0e-3.
constexpr float kSunPieceCells = gpu::SUN_PIECE_CELLS;
constexpr int kSunPieceSplits = gpu::SUN_PIECE_SPLITS;
constexpr float kSunPieceDepthChange = gpu::SUN_PIECE_DEPTH_CHANGE;
constexpr float kSunPieceThinDepth = gpu::SUN_PIECE_THIN_DEPTH;
constexpr float kSunPieceThinWiden = gpu::SUN_PIECE_THIN_WIDEN;
// At most this many pieces a segment before halving: a longer segment's pieces are its length over
// kSunMaxPieces (a power of 2, so the division is exact), as the GPU's (the constants here are
// shaders/shared.h's SUN_PIECE_* and SUN_MAX_PIECES, which sun_segment_integral reads too). A ray through an atmosphere sphere of radius 10,000 (tau 1e-4, the
// depth toward the sun along it all but linear) had been cut into 16-cell pieces, 20,000 of them:
// 500 puffs inside one took trace 1,335 ms a frame at 160x120, against 18 ms without it.
constexpr float kSunMaxPieces = gpu::SUN_MAX_PIECES;

// The accurate technique's sun integrals of a tile, taken together after its rays (SunJobs): a lit piece
// [p, q] of a view segment that began at a, with its ray's media, is a job; its ends are points, whose
// optical depths toward the sun are read from the map in one pass (a piece that starts where the one
// before ended shares its point), and the integrals are then taken in a second pass. Neither pass
// carries anything from one job to the next, so both run over SIMD lanes (AVX2: eight at a time), where
// a ray's walk, one event after another, could not; the jobs whose depth changes fast are then halved
// in rounds that also run over the lanes (refine_pieces).
struct SunJobs {
    // The points: lattice coordinates (SunDepthMap::Ray at t), then the depth there; `points` of them.
    std::vector<float> gu, gv, gs, depth;
    std::size_t points = 0;
    // The jobs, `count` of them: its two points; t at p; q - p; sigma_t; sigma_t (p - a); the view's
    // transmittance at a; the ray (rays) and the tile's pixel; the light it carries per unit of the
    // integral, {0, T(a) sigma_s L_sun P(theta)}.
    std::vector<std::uint32_t> start_point, end_point, ray, pixel;
    std::vector<float> p, length, sigma_t, attenuation, weight;
    std::vector<Float4> light;
    std::size_t count = 0;
    // The passes' working arrays: per job the depths at its ends, the integral, whether to halve it
    // (all ones or 0).
    std::vector<float> od_p, od_q, integral;
    std::vector<std::int32_t> refine;
    std::vector<SunDepthMap::Ray> rays;  // the map rays of the tile's rays, by `ray`
    std::uint64_t shadow_mask = 0;       // the box shadows the tile's rays may meet (tile_shadow_mask)

    // The refinement's pieces, one level of halving a round (refine_pieces): each with
    // the job it belongs to (`owner`), whose light and pixel it shares, and the same fields as a job.
    struct Pieces {
        std::vector<std::uint32_t> owner;
        std::vector<float> p, length, sigma_t, attenuation, weight, od_p, od_q, integral;
        std::vector<std::int32_t> refine;
        // Room for n pieces, padded to a multiple of 8.
        void reserve(std::size_t n) {
            const std::size_t size = (n + 7) / 8 * 8;
            if (p.size() >= size) return;
            for (std::vector<float>* v : {&p, &length, &sigma_t, &attenuation, &weight, &od_p, &od_q, &integral})
                v->resize(size);
            owner.resize(size);
            refine.resize(size);
        }
    };
    Pieces halving, halves;  // the pieces to halve this round, and their halves

    // A packet row's pieces, eight lanes at a time (FastTracer::lit_steps_light, render/fast_tracer.cpp): each one [p, q] in the
    // lanes of `active`, of the row's lit segments at `step` (packet::LitSteps); its depth at q read at
    // point end_point, and at p from the lane's piece before where `shared` (it ended at p), else at
    // point start_point. In float arrays, not Float8 (load8, store8): compiled for any x86-64,
    // alignof(Float8) is 16, so a std::vector of structs that hold one allocates at 16 bytes, where
    // the AVX2 code's aligned moves fault.
    struct LanePiece {
        float p[8], q[8];
        std::int32_t active[8], shared[8];
        std::uint32_t start_point, end_point;
        int step;
    };
    struct LanePieces {
        std::vector<LanePiece> pieces;
        // The points, eight lanes each (8 floats from 8 * index; a std::vector of Float8 would drop its
        // alignment): t along each lane's ray, then the depth there.
        std::vector<float> t, depth;
        std::size_t count = 0, points = 0;
        void clear() { count = points = 0; }
        void add(int step, const Float8& p, const Float8& q, const Int8& active, const Int8& shared, bool start) {
            if (count + 1 > pieces.size()) pieces.resize(std::max<std::size_t>(64, 2 * pieces.size()));
            if (8 * (points + 2) > t.size()) {
                t.resize(std::max<std::size_t>(1024, 2 * t.size()));
                depth.resize(t.size());
            }
            LanePiece& piece = pieces[count++];
            simd::store8(piece.p, p);
            simd::store8(piece.q, q);
            simd::store8(piece.active, active);
            simd::store8(piece.shared, shared);
            piece.step = step;
            if (start) simd::store8(t.data() + 8 * points++, p);
            piece.start_point = std::uint32_t(points - (start ? 1 : 0));  // unread where no lane needs it
            simd::store8(t.data() + 8 * points++, q);
            piece.end_point = std::uint32_t(points - 1);
        }
    };
    LanePieces lanes;
    std::vector<float> mid_u, mid_v, mid_s, mid_depth;  // the halving pieces' midpoints
    std::vector<std::uint32_t> listed_halves;          // a round's halves to halve next, by index

    // The arrays are kept at their largest (a tile's jobs are written by index, not appended: one test
    // of room per job rather than one per array), with room for the padding to a multiple of 8.
    void clear() {
        points = 0;
        count = 0;
        rays.clear();
    }
    // Room for one more job and its two points.
    void make_room() {
        if (count + 8 >= job_room || points + 10 >= point_room) grow();
    }
    // The arrays' room, kept apart from their sizes: make_room's two tests per job then read two
    // members, not four pointers.
    std::size_t job_room = 0, point_room = 0;
    void grow() {
        if (count + 8 >= p.size()) {
            const std::size_t size = std::max<std::size_t>(256, 2 * p.size());
            for (std::vector<float>* v : {&p, &length, &sigma_t, &attenuation, &weight, &od_p, &od_q, &integral})
                v->resize(size);
            for (std::vector<std::uint32_t>* v : {&start_point, &end_point, &ray, &pixel}) v->resize(size);
            refine.resize(size);
            light.resize(size);
        }
        if (points + 10 >= gu.size()) {
            const std::size_t size = std::max<std::size_t>(512, 2 * gu.size());
            for (std::vector<float>* v : {&gu, &gv, &gs, &depth}) v->resize(size);
        }
        job_room = p.size();
        point_room = gu.size();
    }
    void add_point(const SunDepthMap::Ray& r, float t) {
        gu[points] = r.u0 + t * r.du;
        gv[points] = r.v0 + t * r.dv;
        gs[points] = r.s0 + t * r.ds;
        ++points;
    }

    // Where a ray's pieces stand: the end of its last one (its lattice point's index), which the
    // next piece shares if it starts there.
    struct RayEnd {
        float t = -1.0f;
        std::size_t point = 0;
    };
    // The lit piece [p, q] of a segment that began at a, on the ray `ray` (`map`, its entry in `rays`),
    // for tile pixel `pixel`, with the view's transmittance at a and the light it carries per unit of
    // the integral: a job, its end a point, and its start too unless the ray's piece before ended
    // there (the same lattice coordinates, so the same depth), wherever that point lies among the
    // points of the rays whose jobs interleave with it.
    void add(const SunDepthMap::Ray& map, std::uint32_t ray, std::uint32_t pixel, RayEnd& end, float p, float q,
             float a, float sigma_t, float transmittance, const Float4& piece_light) {
        make_room();
        const std::size_t j = count++;
        if (end.t != p) add_point(map, p);
        start_point[j] = std::uint32_t(end.t != p ? points - 1 : end.point);
        add_point(map, q);
        end_point[j] = std::uint32_t(points - 1);
        end = {q, points - 1};
        this->p[j] = p;
        length[j] = q - p;
        this->sigma_t[j] = sigma_t;
        attenuation[j] = sigma_t * (p - a);
        weight[j] = transmittance;
        this->ray[j] = ray;
        this->pixel[j] = pixel;
        light[j] = piece_light;
    }
};

// Job i's light times `amount`, into its pixel's sum.
inline void add_job_light(const SunJobs& jobs, dvec3* pixel_sums, std::size_t i, float amount) {
    const Float4 light = jobs.light[i] * amount;
    dvec3& out = pixel_sums[jobs.pixel[i]];
    out.x += double(light[1]);
    out.y += double(light[2]);
    out.z += double(light[3]);
}

// Piece `from` of `source` (the jobs, or a round's halves: both hold these arrays) into slot `to`
// of `target`, as a piece of job `owner`.
template <class Source>
inline void copy_piece(const Source& source, std::size_t from, SunJobs::Pieces& target, std::size_t to,
                       std::uint32_t owner) {
    target.owner[to] = owner;
    target.p[to] = source.p[from];
    target.length[to] = source.length[from];
    target.sigma_t[to] = source.sigma_t[from];
    target.attenuation[to] = source.attenuation[from];
    target.weight[to] = source.weight[from];
    target.od_p[to] = source.od_p[from];
    target.od_q[to] = source.od_q[from];
    target.integral[to] = source.integral[from];
}

// Eight pieces' integrals, piece_integrals' closed form: depths od_p and od_q at the ends, length
// len, sigma_t, attenuation sigma_t (p - a), weight T(a); whether each calls for halving into
// `halve` (all ones, or 0).
[[gnu::always_inline]] inline Float8 piece_integral8(const Float8& od_p, const Float8& od_q, const Float8& len,
                                                     const Float8& sigma_t, const Float8& attenuation,
                                                     const Float8& weight, Int8& halve) {
    const Float8 change = od_q - od_p;
    const Float8 x = sigma_t * len + change;
    // The integrand at p, exp(-sigma_t (p - a) - depth(p)).
    const Float8 at_p = exp_minus8(attenuation + od_p);
    const Float8 magnitude = Float8(Int8(change) & 0x7fffffff);
    const Float8 thin = sigma_t * len * (1.0f / kSunPieceThinDepth);
    const Float8 share = thin < 1.0f ? thin : Float8{} + 1.0f;  // of the light, the piece's media scatter
    halve = weight * at_p * share * magnitude > kSunPieceDepthChange;
    // The integrand at q from its own exponent, not at_p exp(-x) (linear_exponent_integral8).
    const Float8 at_q = exp_minus8(attenuation + sigma_t * len + od_q);
    return linear_exponent_integral8(x, at_p, at_q, len);
}

// Over pieces [0, padded), eight at a time: the integral over each with the depth linear along it,
// and whether the light it may carry (the view's transmittance to its segment, `weight`, times the
// integrand at its start) times its change of depth calls for halving it (all ones, or 0).
[[gnu::always_inline]] inline void piece_integrals(const float* od_p, const float* od_q, const float* length,
                                                   const float* sigma_t, const float* attenuation,
                                                   const float* weight, std::size_t padded, float* integral,
                                                   std::int32_t* refine) {
    for (std::size_t i = 0; i < padded; i += 8) {
        Int8 halve;
        simd::store8(integral + i, piece_integral8(load8(od_p + i), load8(od_q + i), load8(length + i),
                                                   load8(sigma_t + i), load8(attenuation + i), load8(weight + i),
                                                   halve));
        simd::store8(refine + i, halve);
    }
}

// The refinement, where the depth changes fast: each of the `count` pieces in jobs.halving is
// halved, the depth read at its midpoint, and its halves' light put in place of its own; the
// halves that call for it are halved in the next round, up to kSunPieceSplits rounds (down to a
// sixteenth of a piece). A round takes its reads and closed forms eight at a time, as the jobs'
// pass: one level a round, where the GPU's sun_segment_integral (shaders/exact_integrator.glsl)
// halves depth first, one piece at a time, but the same pieces with the same tests.
template <class Gather>
void refine_pieces(const SunDepthMap& map, SunJobs& jobs, std::size_t count, dvec3* pixel_sums, const Gather& gather) {
    SunJobs::Pieces& halving = jobs.halving;
    SunJobs::Pieces& halves = jobs.halves;
    for (int level = 1; level <= kSunPieceSplits && count > 0; ++level) {
        const std::size_t padded_mid = (count + 7) / 8 * 8;
        if (jobs.mid_u.size() < padded_mid)
            for (std::vector<float>* v : {&jobs.mid_u, &jobs.mid_v, &jobs.mid_s, &jobs.mid_depth})
                v->resize(std::max(padded_mid, 2 * v->size()));
        halves.reserve(2 * count);
        if (jobs.listed_halves.size() < 2 * count)
            jobs.listed_halves.resize(2 * std::max(count, jobs.listed_halves.size()));
        for (std::size_t r = 0; r < count; ++r) {
            const std::uint32_t owner = halving.owner[r];
            const float p = halving.p[r], q = p + halving.length[r], mid = 0.5f * (p + q);
            const SunDepthMap::Ray& map = jobs.rays[jobs.ray[owner]];
            jobs.mid_u[r] = map.u0 + mid * map.du;
            jobs.mid_v[r] = map.v0 + mid * map.dv;
            jobs.mid_s[r] = map.s0 + mid * map.ds;
            const float sigma_t = halving.sigma_t[r], attenuation = halving.attenuation[r];
            const float weight = halving.weight[r];
            for (std::size_t h : {2 * r, 2 * r + 1}) {
                halves.owner[h] = owner;
                halves.sigma_t[h] = sigma_t;
                halves.weight[h] = weight;
            }
            halves.p[2 * r] = p;
            halves.length[2 * r] = mid - p;
            halves.attenuation[2 * r] = attenuation;
            halves.od_p[2 * r] = halving.od_p[r];
            halves.p[2 * r + 1] = mid;
            halves.length[2 * r + 1] = q - mid;
            halves.attenuation[2 * r + 1] = attenuation + sigma_t * (mid - p);
            halves.od_q[2 * r + 1] = halving.od_q[r];
        }
        for (std::size_t m = count; m < padded_mid; ++m) jobs.mid_u[m] = jobs.mid_v[m] = jobs.mid_s[m] = -1.0f;
        map.optical_depths(jobs.mid_u.data(), jobs.mid_v.data(), jobs.mid_s.data(), jobs.mid_depth.data(),
                                count, gather);
        for (std::size_t r = 0; r < count; ++r) halves.od_q[2 * r] = halves.od_p[2 * r + 1] = jobs.mid_depth[r];
        const std::size_t n = 2 * count, padded = (n + 7) / 8 * 8;
        for (std::size_t h = n; h < padded; ++h)
            halves.od_p[h] = halves.od_q[h] = halves.length[h] = halves.sigma_t[h] = halves.attenuation[h] =
                halves.weight[h] = 0.0f;
        piece_integrals(halves.od_p.data(), halves.od_q.data(), halves.length.data(), halves.sigma_t.data(),
                        halves.attenuation.data(), halves.weight.data(), padded, halves.integral.data(),
                        halves.refine.data());
        for (std::size_t r = 0; r < count; ++r)
            add_job_light(jobs, pixel_sums, halving.owner[r],
                          halves.integral[2 * r] + halves.integral[2 * r + 1] - halving.integral[r]);
        if (level == kSunPieceSplits) break;
        // The halves to halve next round: listed by index without a branch (which they are, the
        // branch predictor could not know), then only those copied (copying every half, the list
        // advancing past those to halve, moved nine fields a half where most are not halved).
        halving.reserve(n);
        std::uint32_t* const listed = jobs.listed_halves.data();
        std::size_t next = 0;
        for (std::size_t h = 0; h < n; ++h) {
            listed[next] = std::uint32_t(h);
            next -= std::size_t(std::int64_t(halves.refine[h]));
        }
        for (std::size_t r = 0; r < next; ++r) copy_piece(halves, listed[r], halving, r, halves.owner[listed[r]]);
        count = next;
    }
}

// The integrals of the tile's jobs (add_sun_pieces), each light times its integral added to its
// pixel's sum. In passes over the jobs that carry nothing from one to the next, so that the compiler
// takes them over SIMD lanes: the depths at the points; the closed form over each piece, with the
// depth linear along it, and whether the light it may carry times its change of depth calls for
// halving it; the sums; then the halving where called for (refine_pieces).
template <class Gather>
void resolve(const SunDepthMap& map, SunJobs& jobs, dvec3* pixel_sums, const Gather& gather) {
    const std::size_t n = jobs.count;
    if (n == 0) return;
    // Padded to a multiple of 8 (make_room left the room): points outside the lattice, jobs that
    // add nothing.
    for (std::size_t m = jobs.points; m % 8 != 0; ++m) jobs.gu[m] = jobs.gv[m] = jobs.gs[m] = -1.0f;
    map.optical_depths(jobs.gu.data(), jobs.gv.data(), jobs.gs.data(), jobs.depth.data(), jobs.points,
                            gather);
    const std::size_t padded = (n + 7) / 8 * 8;
    for (std::size_t i = 0; i < n; ++i) {
        jobs.od_p[i] = jobs.depth[jobs.start_point[i]];
        jobs.od_q[i] = jobs.depth[jobs.end_point[i]];
    }
    for (std::size_t i = n; i < padded; ++i)
        jobs.od_p[i] = jobs.od_q[i] = jobs.length[i] = jobs.sigma_t[i] = jobs.attenuation[i] = jobs.weight[i] = 0.0f;
    piece_integrals(jobs.od_p.data(), jobs.od_q.data(), jobs.length.data(), jobs.sigma_t.data(),
                    jobs.attenuation.data(), jobs.weight.data(), padded, jobs.integral.data(), jobs.refine.data());
    // The sums, and the jobs to refine listed without a branch (which they are, the branch predictor
    // could not know), as the first round's pieces to halve.
    const float* integral = jobs.integral.data();
    const std::int32_t* refine = jobs.refine.data();
    SunJobs::Pieces& halving = jobs.halving;
    halving.reserve(n);
    std::size_t to_refine = 0;
    // A pixel's jobs mostly come one after another (a ray's pieces), so their light is summed in a
    // register while the pixel stays the same: added to the pixel's sum in memory job by job, each
    // addition waited for the one before to be stored and read back.
    std::uint32_t pixel = jobs.pixel[0];
    Double4 run{};  // lanes 1-3, as a job's light
    const auto add_run = [&] {
        dvec3& out = pixel_sums[pixel];
        out.x += run[1];
        out.y += run[2];
        out.z += run[3];
    };
    for (std::size_t i = 0; i < n; ++i) {
        if (jobs.pixel[i] != pixel) {
            add_run();
            run = Double4{};
            pixel = jobs.pixel[i];
        }
        run += __builtin_convertvector(jobs.light[i] * integral[i], Double4);
        halving.owner[to_refine] = std::uint32_t(i);
        to_refine -= std::size_t(std::int64_t(refine[i]));  // refine[i] is -1 or 0
    }
    add_run();
    for (std::size_t r = 0; r < to_refine; ++r) copy_piece(jobs, halving.owner[r], halving, r, halving.owner[r]);
    refine_pieces(map, jobs, to_refine, pixel_sums, gather);
}

}  // namespace brume::sun_jobs
