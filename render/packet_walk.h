// trace's walk (render/fast_tracer.cpp FastTracer::radiance) for eight rays at once, one per SIMD lane
// (render/simd8.h), where a tile lists few spheres: a tile row's eight pixels take every event of the
// tile's spheres (at most kMaxSpheres, so at most 16 events a ray), sorted in each lane by a fixed
// network, then integrated in step, a lane masked off where its ray has no event left or stopped. On such tiles the walk one ray at a time spent most of a pixel on
// what a ray does once, not on its events: at 2 layers (one sphere on every ray), 140 cycles a pixel.
//
// Exact as the one-ray walk is: the same events (chords by the same test, clipped at the same opaque
// surface), in the same total order (distance's bits, then scene index, then exit after entry), the same
// arithmetic in each lane; the images agree but for where the compiler fuses a multiply-add
// (tests/test_fast_tracer.cpp holds the two together).
#pragma once

#include "render/compensated_sum.h"
#include "render/simd8.h"
#include "render/simd8_math.h"

#include <array>
#include <cstdint>
#include <utility>

namespace brume::packet {

using simd::Float8;
using simd::Int8;
using Uint8 = std::uint32_t __attribute__((vector_size(32)));

// A tile with more spheres takes the one-ray walk: the network for 32 events costs more than the walk
// saves where lists are long.
constexpr int kMaxSpheres = 8;

// Which light the walk integrates, as the one-ray walk's integrate(): kPlain, a scene without shadows
// or emission (sigma_s L_s); kPerSphere, the per-sphere technique (the sun's light scattered by the
// part of sigma_s that the sun lights at the spheres' centres), emission included, and any scene with
// emission but no shadows; kAccurate, the accurate technique, whose lit segments the walk writes down
// (LitSteps) for the tracer to take the sun's light over, and whose walk adds the ambient light and
// emission.
enum class Light { kPlain, kPerSphere, kAccurate };

// The quantities of a medium that a walk sums per lane (LaneMedia), as its tables name them.
enum class Quantity { kSigmaT, kSigmaR, kSigmaG, kSigmaB, kSunR, kSunG, kSunB, kEmissionR, kEmissionG, kEmissionB };

// A walk's table of quantity q, by rank: `spheres`' member of that name (packet::Spheres' lanes, or
// packet::OrderedSpheres' arrays).
template <class S>
[[gnu::always_inline]] inline decltype(auto) media_table(const S& spheres, Quantity q) {
    switch (q) {
        case Quantity::kSigmaT: return (spheres.sigma_t);
        case Quantity::kSigmaR: return (spheres.sigma_r);
        case Quantity::kSigmaG: return (spheres.sigma_g);
        case Quantity::kSigmaB: return (spheres.sigma_b);
        case Quantity::kSunR: return (spheres.sun_r);
        case Quantity::kSunG: return (spheres.sun_g);
        case Quantity::kSunB: return (spheres.sun_b);
        case Quantity::kEmissionR: return (spheres.emission_r);
        case Quantity::kEmissionG: return (spheres.emission_g);
        default: return (spheres.emission_b);
    }
}

// A tile's spheres as the packet reads them, in the tile's order n: the chord test's values (centre
// relative to the eye, r^2, |c|^2 - r^2), each one's rank by scene index (the events' order among equal
// distances), and by rank, in tables of lanes, each one's sigma_t and sigma_s, the part of sigma_s the
// sun lights at its centre (kPerSphere) and tau * emission.
struct Spheres {
    int count = 0;
    float cx[kMaxSpheres], cy[kMaxSpheres], cz[kMaxSpheres], r2[kMaxSpheres], c_minus_r2[kMaxSpheres];
    std::uint32_t rank[kMaxSpheres];
    // The tile's columns [first, last) and rows its pixel rectangle covers (render/tile_bins.h): the
    // rays that may meet it, which alone test it (as list_tile's).
    int columns[kMaxSpheres][2], rows[kMaxSpheres][2];
    Float8 sigma_t{}, sigma_r{}, sigma_g{}, sigma_b{};
    Float8 sun_r{}, sun_g{}, sun_b{};
    Float8 emission_r{}, emission_g{}, emission_b{};
    bool emits = false;  // whether any of them has emission
};

// Eight rays, lane by lane: unit direction, the opaque surface's distance, L_ambient + L_sun P(theta),
// L_sun P(theta), L_ambient, and per sphere n whether the lane's ray tests it (all ones: its pixel lies
// in the sphere's rectangle).
struct Rays {
    Float8 dx, dy, dz, t_opaque;
    Float8 source_r, source_g, source_b;
    Float8 sun_phase_r, sun_phase_g, sun_phase_b;
    Float8 ambient_r, ambient_g, ambient_b;
    Int8 listed[kMaxSpheres];
};

// kAccurate's lit segments of a row's walk, step by step, all lanes at once: at step k the lanes of
// lit[k] integrated the segment [a, b] with sigma_t, the light {sigma_s L_sun P(theta) T(a)} and the
// transmittance T(a), as the one-ray walk's add_sun_pieces takes them. The walk only writes them down
// (no lane's values taken out of the registers inside it); the tracer takes the sun's light over them
// after the walk (FastTracer::lit_steps_light), eight lanes at a time.
struct LitSteps {
    static constexpr int kMaxSteps = 128;  // 2 * kMaxOrderedSpheres (render/ordered_walk.h)
    Float8 a[kMaxSteps], b[kMaxSteps], sigma_t[kMaxSteps], transmittance[kMaxSteps];
    Float8 light_r[kMaxSteps], light_g[kMaxSteps], light_b[kMaxSteps];
    Int8 lit[kMaxSteps];
    int steps = 0;  // the steps walked: lit[k] holds for k < steps

    // Step k's lit segments, in the lanes of `segment`.
    [[gnu::always_inline]] void record(int k, const Int8& segment, const Float8& from, const Float8& to,
                                       const Float8& sigma, const Float8& t_at_from, const Float8& r,
                                       const Float8& g, const Float8& bl) {
        lit[k] = segment;
        a[k] = from;
        b[k] = to;
        sigma_t[k] = sigma;
        transmittance[k] = t_at_from;
        light_r[k] = r;
        light_g[k] = g;
        light_b[k] = bl;
    }
};

// What the media send to the eye in each lane, the transmittance left, and whether the ray stopped
// below min_transmittance (all ones: then nothing behind the media is added, as in the one-ray walk).
struct Result {
    Float8 r{}, g{}, b{}, transmittance{};
    Int8 stopped{};
};

// Whether any lane of a mask is set: the halves folded in registers, then two 64-bit words, where lane
// by lane it took eight extractions (2 layers at 800x600, one thread: 6.4 to 6.2 ms a frame).
[[gnu::always_inline]] inline bool any(const Int8& mask) {
    using Int4 = std::int32_t __attribute__((vector_size(16)));
    using Word2 = std::uint64_t __attribute__((vector_size(16)));
    const Int4 folded = __builtin_shufflevector(mask, mask, 0, 1, 2, 3) | __builtin_shufflevector(mask, mask, 4, 5, 6, 7);
    const Word2 words = Word2(folded);
    return (words[0] | words[1]) != 0;
}

// Batcher's odd-even merge sort of P keys (P a power of two): its compare-exchange pairs, in order.
template <int P>
constexpr auto merge_sort_network() {
    constexpr int pairs = [] {
        int n = 0;
        for (int p = 1; p < P; p *= 2)
            for (int k = p; k >= 1; k /= 2)
                for (int j = k % p; j + k < P; j += 2 * k)
                    for (int i = 0; i < k && i + j + k < P; ++i)
                        if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) ++n;
        return n;
    }();
    std::array<std::pair<int, int>, pairs> out{};
    int n = 0;
    for (int p = 1; p < P; p *= 2)
        for (int k = p; k >= 1; k /= 2)
            for (int j = k % p; j + k < P; j += 2 * k)
                for (int i = 0; i < k && i + j + k < P; ++i)
                    if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) out[std::size_t(n++)] = {i + j, i + j + k};
    return out;
}

// The running sums of the media each lane is in: sigma_t and sigma_s; kPerSphere's sun-lit part of
// sigma_s; tau * emission (all but kPlain's).
struct LaneMedia {
    Float8 sigma_t{}, sigma_r{}, sigma_g{}, sigma_b{};
    Float8 sun_r{}, sun_g{}, sun_b{};
    Float8 emission_r{}, emission_g{}, emission_b{};
};
// Each running sum as the one-ray walk keeps it: the value the segments read, value = sum + error, with
// sum and error stepped as a compensated sum (render/compensated_sum.h).
struct LaneSums {
    LaneMedia value, sum, error;
};

// The segment [t_prev, t_prev + len] of the lanes of `segment`, each lane as the one-ray walk's
// integrate() adds it, operation for operation: its light into `out`, its transmittance, and the
// lanes it stops (returned). kAccurate's sun light goes to lit(light_r, light_g, light_b), with
// out.transmittance still that at the segment's start.
template <Light kLight, class Lit>
[[gnu::always_inline]] inline Int8 integrate_segment(Result& out, const LaneMedia& m, const Rays& rays,
                                                     const Int8& segment, const Float8& len, float min_transmittance,
                                                     const Lit& lit) {
    const Float8 x = m.sigma_t * len;
    Float8 segment_transmittance, w;
    simd::segment_transmittance8(x, len, segment_transmittance, w);
    const Float8 tw = out.transmittance * w;
    if constexpr (kLight == Light::kPlain) {
        out.r = segment ? out.r + m.sigma_r * rays.source_r * tw : out.r;
        out.g = segment ? out.g + m.sigma_g * rays.source_g * tw : out.g;
        out.b = segment ? out.b + m.sigma_b * rays.source_b * tw : out.b;
    } else if constexpr (kLight == Light::kAccurate) {
        lit(m.sigma_r * rays.sun_phase_r * out.transmittance, m.sigma_g * rays.sun_phase_g * out.transmittance,
            m.sigma_b * rays.sun_phase_b * out.transmittance);
        out.r = segment ? out.r + (m.sigma_r * rays.ambient_r + m.emission_r) * tw : out.r;
        out.g = segment ? out.g + (m.sigma_g * rays.ambient_g + m.emission_g) * tw : out.g;
        out.b = segment ? out.b + (m.sigma_b * rays.ambient_b + m.emission_b) * tw : out.b;
    } else {
        out.r = segment ? out.r + (m.sigma_r * rays.source_r - (m.sigma_r - m.sun_r) * rays.sun_phase_r + m.emission_r) * tw
                        : out.r;
        out.g = segment ? out.g + (m.sigma_g * rays.source_g - (m.sigma_g - m.sun_g) * rays.sun_phase_g + m.emission_g) * tw
                        : out.g;
        out.b = segment ? out.b + (m.sigma_b * rays.source_b - (m.sigma_b - m.sun_b) * rays.sun_phase_b + m.emission_b) * tw
                        : out.b;
    }
    out.transmittance = segment ? out.transmittance * segment_transmittance : out.transmittance;
    return segment & (out.transmittance < min_transmittance);
}

// A walk's step k to its events at t, in the lanes of `live`: the segment since t_prev integrated
// where a lane is in a medium (integrate_segment; kAccurate's lit segments written down as step k of
// lit_steps), the lanes it stops added to `stopped`. Returns the lanes that step onto their events
// (live and not stopped), t_prev moved to t there. One copy for the packet and ordered walks.
template <Light kLight>
[[gnu::always_inline]] inline Int8 walk_segment(int k, const Float8& t, const Int8& live, const Int8& inside,
                                                const LaneMedia& media, const Rays& rays, float min_transmittance,
                                                Result& out, Float8& t_prev, Int8& stopped, LitSteps& lit_steps) {
    const Float8 len = t - t_prev;
    const Int8 segment = live & (len > 0.0f) & (inside > 0);
    Int8 stops{};
    if constexpr (kLight == Light::kAccurate) lit_steps.lit[k] = segment;
    // No lane in a medium (every ray's first event, a gap between spheres): nothing to integrate.
    if (any(segment)) {
        const auto lit = [&](const Float8& light_r, const Float8& light_g, const Float8& light_b) {
            lit_steps.record(k, segment, t_prev, t, media.sigma_t, out.transmittance, light_r, light_g, light_b);
        };
        stops = integrate_segment<kLight>(out, media, rays, segment, len, min_transmittance, lit);
        stopped |= stops;
    }
    const Int8 step = live & ~stops;
    t_prev = step ? t : t_prev;
    return step;
}

// Enter or leave the event's medium in the lanes of `step` (exit: 1 where it is an exit): the
// one-ray walk's sums, lane by lane, each plus or minus value(quantity), the medium's in each lane, as
// compensated sums; leaving clamps at 0, and back in free space (inside, after the step, 0) the sums
// are exactly 0.
// `emits`: whether any of the tile's spheres has emission; where none has, its sums stay 0 without
// being stepped (three of the seven sums of a shadowed fog's step).
template <Light kLight, class Value>
[[gnu::always_inline]] inline void step_media(LaneSums& m, Int8& inside, const Int8& step, const Int8& exit,
                                              bool emits, const Value& value) {
    inside = step ? inside + 1 - 2 * exit : inside;
    const Int8 exit_mask = Int8{} - exit;
    const Int8 free_mask = inside == 0;
    const Float8 sign = 1.0f - 2.0f * __builtin_convertvector(exit, Float8);
    const auto advance = [&](Float8 LaneMedia::*field, Quantity q) {
        Float8 sum = m.sum.*field, error = m.error.*field;
        compensated_step(sum, error, sign * value(q), exit_mask, free_mask);
        m.sum.*field = step ? sum : m.sum.*field;
        m.error.*field = step ? error : m.error.*field;
        m.value.*field = m.sum.*field + m.error.*field;
    };
    advance(&LaneMedia::sigma_t, Quantity::kSigmaT);
    advance(&LaneMedia::sigma_r, Quantity::kSigmaR);
    advance(&LaneMedia::sigma_g, Quantity::kSigmaG);
    advance(&LaneMedia::sigma_b, Quantity::kSigmaB);
    if constexpr (kLight == Light::kPerSphere) {
        advance(&LaneMedia::sun_r, Quantity::kSunR);
        advance(&LaneMedia::sun_g, Quantity::kSunG);
        advance(&LaneMedia::sun_b, Quantity::kSunB);
    }
    if (kLight != Light::kPlain && emits) {
        advance(&LaneMedia::emission_r, Quantity::kEmissionR);
        advance(&LaneMedia::emission_g, Quantity::kEmissionG);
        advance(&LaneMedia::emission_b, Quantity::kEmissionB);
    }
}

// Sphere n's chord [start, end] along each lane's ray t d, in the lanes of `listed`, as the one-ray walk
// takes it (chord_discriminant, then its roots; clipped at the eye and the opaque surface); returns the
// lanes where it is not empty.
template <class S>
[[gnu::always_inline]] inline Int8 lane_chord(const S& spheres, int n, const Rays& rays, const Int8& listed,
                                              Float8& start, Float8& end) {
    const Float8 zero{};
    const float cx = spheres.cx[n], cy = spheres.cy[n], cz = spheres.cz[n];
    const Float8 b = cx * rays.dx + cy * rays.dy + cz * rays.dz;
    const Float8 px = cx - b * rays.dx, py = cy - b * rays.dy, pz = cz - b * rays.dz;
    const Float8 disc = spheres.r2[n] - (px * px + py * py + pz * pz);
    const Int8 meets = listed & (disc > 0.0f);
    const Float8 s = simd::sqrt8(meets ? disc : zero);
    Float8 q = b > 0.0f ? b + s : b - s;  // |q| >= s > 0 where it meets
    q = meets ? q : zero + 1.0f;
    const Float8 ta = q, tb = spheres.c_minus_r2[n] / q;
    // std::max(std::min(ta, tb), 0.0f) and std::min(std::max(ta, tb), t_opaque), operand for operand.
    const Float8 near = tb < ta ? tb : ta, far = ta < tb ? tb : ta;
    start = near < 0.0f ? zero : near;
    end = rays.t_opaque < far ? rays.t_opaque : far;
    return meets & (end > start);
}

// The walk of the rays through the spheres, P event slots per lane (P >= 2 * spheres.count, a power of
// two). min_transmittance: the scene's early stop. kAccurate's lit segments go to `lit_steps` (which
// the other lights leave alone).
template <int P, Light kLight>
[[gnu::always_inline]] inline Result walk(const Spheres& spheres, const Rays& rays, float min_transmittance,
                                          LitSteps& lit_steps) {
    static_assert(P >= 2 && P <= 2 * kMaxSpheres && (P & (P - 1)) == 0);
    // The events: a distance's bits (>= +0 where the chord is taken, so they order as the distances
    // do; -0 orders last, as in the one-ray walk's keys) and rank * 2 + exit. A slot with no event holds
    // +inf, past every event, and is never integrated.
    constexpr std::uint32_t kNone = 0x7f800000u;  // +inf
    Uint8 key[P], id[P];
    for (int e = 0; e < P; ++e) {
        key[e] = Uint8{} + kNone;
        id[e] = Uint8{} + 2u * std::uint32_t(kMaxSpheres);
    }
    const Float8 zero{};
    for (int n = 0; n < spheres.count; ++n) {
        Float8 start, end;
        const Int8 taken = lane_chord(spheres, n, rays, rays.listed[n], start, end);
        key[2 * n] = taken ? Uint8(start) : key[2 * n];
        key[2 * n + 1] = taken ? Uint8(end) : key[2 * n + 1];
        const std::uint32_t entry = 2u * spheres.rank[n];
        id[2 * n] = taken ? Uint8{} + entry : id[2 * n];
        id[2 * n + 1] = taken ? Uint8{} + (entry + 1u) : id[2 * n + 1];
    }
    // Sorted in each lane by (distance bits, id).
    static constexpr auto network = merge_sort_network<P>();
    for (const auto& [i, j] : network) {
        const Int8 swap = (key[j] < key[i]) | ((key[j] == key[i]) & (id[j] < id[i]));
        const Uint8 ki = key[i], kj = key[j], ii = id[i], ij = id[j];
        key[i] = swap ? kj : ki;
        key[j] = swap ? ki : kj;
        id[i] = swap ? ij : ii;
        id[j] = swap ? ii : ij;
    }

    // Front to back (shaders/exact_integrator.glsl), a lane at a time where its events lie.
    Result out;
    out.transmittance = zero + 1.0f;
    LaneSums media;
    Float8 t_prev{};
    Int8 inside{}, stopped{};
    int walked = 0;  // the slots walked
    for (int e = 0; e < P; ++e) {
        const Int8 live = (key[e] < kNone) & ~stopped;
        // Every lane has no event left: the slots after this one hold none either.
        if (!any(live)) break;
        walked = e + 1;
        const Int8 step = walk_segment<kLight>(e, Float8(key[e]), live, inside, media.value, rays, min_transmittance, out,
                                               t_prev, stopped, lit_steps);
        const Int8 rank = Int8(id[e] >> 1u);
        step_media<kLight>(media, inside, step, Int8(id[e] & 1u), spheres.emits,
                           [&](Quantity q) { return simd::lookup8(media_table(spheres, q), rank); });
    }
    if constexpr (kLight == Light::kAccurate) lit_steps.steps = walked;
    out.stopped = stopped;
    return out;
}

}  // namespace brume::packet
