// trace's walk for eight rays at once where a tile lists more spheres than the packet walk takes
// (render/packet_walk.h, at most 8) but not many more (kMaxOrderedSpheres): the fog banks and cloud
// layers whose large spheres cover dozens of neighbouring tiles. The eight pixels of a tile row meet
// those spheres' surfaces in nearly the same order, so the row sorts its events once, by one lane's
// distances (insertion, from the tile's near-to-far order), and each lane then puts that order right
// for itself by a few passes of odd-even transposition over its own events, in SIMD lanes: near a
// sphere's silhouette its chord's ends close in fast from pixel to pixel and cross other spheres'
// events, so more than half the lanes of fog-bank's rows disagree with any one order, but by a place
// or two. The lanes are then integrated in step, as the packet walk's, each step's media read by one
// load where every lane that steps takes the same sphere, and by a gather where they differ.
//
// Exact as the one-ray walk is. After the passes each lane checks that its events' keys (distance
// bits, then scene index, then exit after entry: the one-ray walk's total order) strictly increase;
// a lane where they do not is `failed` and left alone here, and the caller walks its ray one at a
// time. A lane that passes takes its own events in its own order with the packet walk's arithmetic,
// so its image is the one-ray walk's (tests/test_fast_tracer.cpp holds them together).
#pragma once

#include "render/packet_walk.h"

#include <cstdint>

namespace brume::packet {

// Up to this many spheres a tile row shares its order; past it the one-ray walk's lists do (the
// vdb-cloud and explosion tiles of 100-250 small spheres, whose order changes from pixel to pixel).
constexpr int kMaxOrderedSpheres = 64;
// The odd-even transposition passes each lane's events take after the shared order.
constexpr int kOrderPasses = 4;

// A tile's spheres as the ordered walk reads them, in the tile's order n (near to far by bound): as
// packet::Spheres, by_rank the tile's order of each rank, and the media by rank, gathered per lane.
struct OrderedSpheres {
    int count = 0;
    float cx[kMaxOrderedSpheres], cy[kMaxOrderedSpheres], cz[kMaxOrderedSpheres];
    float r2[kMaxOrderedSpheres], c_minus_r2[kMaxOrderedSpheres];
    std::uint32_t rank[kMaxOrderedSpheres];
    std::uint8_t by_rank[kMaxOrderedSpheres];
    int columns[kMaxOrderedSpheres][2], rows[kMaxOrderedSpheres][2];
    float sigma_t[kMaxOrderedSpheres], sigma_r[kMaxOrderedSpheres], sigma_g[kMaxOrderedSpheres],
        sigma_b[kMaxOrderedSpheres];
    float sun_r[kMaxOrderedSpheres], sun_g[kMaxOrderedSpheres], sun_b[kMaxOrderedSpheres];
    float emission_r[kMaxOrderedSpheres], emission_g[kMaxOrderedSpheres], emission_b[kMaxOrderedSpheres];
    bool emits = false;  // whether any of them has emission
};

// A row's events: per sphere n the lanes that meet it (`taken`) and the key bits of its entry and exit
// in each; the shared order's two runs, as (the order lane's distance bits << 32) | (rank * 2 + exit);
// then each lane's own events, slot k its k-th, keys and ids (one spare slot past the last).
static_assert(LitSteps::kMaxSteps >= 2 * kMaxOrderedSpheres);
struct OrderedEvents {
    Uint8 entry[kMaxOrderedSpheres], exit[kMaxOrderedSpheres];
    Int8 taken[kMaxOrderedSpheres];
    std::uint64_t entries[kMaxOrderedSpheres + 1], exits[kMaxOrderedSpheres + 1];
    Uint8 key[2 * kMaxOrderedSpheres + 1], id[2 * kMaxOrderedSpheres + 1];
};

// Bit l set where lane l of the mask is set (all ones or 0): SSE's sign-bit masks of the two halves,
// on any x86-64, where a loop over the lanes took eight extractions.
[[gnu::always_inline]] inline int simd_mask(const Int8& mask) {
#if defined(__x86_64__) && defined(__GNUC__)
    using Float4 = float __attribute__((vector_size(16)));
    const Float8 f = Float8(mask);
    const Float4 lo = __builtin_shufflevector(f, f, 0, 1, 2, 3), hi = __builtin_shufflevector(f, f, 4, 5, 6, 7);
    return _mm_movemask_ps(__m128(lo)) | (_mm_movemask_ps(__m128(hi)) << 4);
#else
    int bits = 0;
    for (int l = 0; l < 8; ++l) bits |= (mask[l] != 0 ? 1 : 0) << l;
    return bits;
#endif
}

// The smallest of eight unsigned lanes.
[[gnu::always_inline]] inline std::uint32_t min_lane(Uint8 v) {
    using Uint4 = std::uint32_t __attribute__((vector_size(16)));
    const Uint4 lo = __builtin_shufflevector(v, v, 0, 1, 2, 3), hi = __builtin_shufflevector(v, v, 4, 5, 6, 7);
    Uint4 m = lo < hi ? lo : hi;
    const Uint4 m2 = __builtin_shufflevector(m, m, 2, 3, 0, 1);
    m = m < m2 ? m : m2;
    const Uint4 m1 = __builtin_shufflevector(m, m, 1, 0, 3, 2);
    m = m < m1 ? m : m1;
    return m[0];
}

// Appends `key` to the ascending run[0, size) by insertion: the tile's spheres come near to far by
// bound, so an entry lands at or near the back, and most exits a few places from it.
[[gnu::always_inline]] inline void insert_sorted(std::uint64_t* run, int& size, std::uint64_t key) {
    int i = size++;
    for (; i > 0 && run[i - 1] > key; --i) run[i] = run[i - 1];
    run[i] = key;
}

// The walk of tile row `row`'s rays through the spheres. Lanes whose order the passes could not put
// right come back in `failed` (all ones), their results undefined; the others' as packet::walk's.
// `events` is the row's scratch; `gather` reads a table by lane (render/simd8.h). kAccurate's lit
// segments go to `lit_steps`.
template <Light kLight, class Gather>
[[gnu::always_inline]] inline Result ordered_walk(const OrderedSpheres& spheres, const Rays& rays, int row,
                                                  float min_transmittance, OrderedEvents& events, Int8& failed,
                                                  const Gather& gather, LitSteps& lit_steps) {
    constexpr std::uint32_t kNone = 0x7f800000u;  // +inf: no event
    constexpr int kOrderLane = 4;                 // whose distances order the events where it has them
    const Float8 zero{};
    const Uint8 none = Uint8{} + kNone;
    const Int8 lane{0, 1, 2, 3, 4, 5, 6, 7};
    int entry_count = 0, exit_count = 0;
    for (int n = 0; n < spheres.count; ++n) {
        // Tested by the lanes whose pixels its rectangle covers (as list_tile's), then packet::walk's chord.
        const bool row_covered = row >= spheres.rows[n][0] && row < spheres.rows[n][1];
        const Int8 listed = (lane >= spheres.columns[n][0]) & (lane < spheres.columns[n][1]) & (row_covered ? -1 : 0);
        Float8 start, end;
        const Int8 taken = lane_chord(spheres, n, rays, listed, start, end);
        events.taken[n] = taken;
        events.entry[n] = taken ? Uint8(start) : none;
        events.exit[n] = taken ? Uint8(end) : none;
        if (!any(taken)) continue;
        // The event's place: its key in the order lane where that lane has it, else its least over
        // the lanes that do. One lane's keys for most events, so that events tied in every lane
        // (spheres that all end at the ground) keep their tie, and so their order by id.
        const std::uint64_t id = 2u * spheres.rank[n];
        const bool ordered_by_lane = taken[kOrderLane] != 0;
        const std::uint32_t entry_at = ordered_by_lane ? events.entry[n][kOrderLane] : min_lane(events.entry[n]);
        const std::uint32_t exit_at = ordered_by_lane ? events.exit[n][kOrderLane] : min_lane(events.exit[n]);
        insert_sorted(events.entries, entry_count, (std::uint64_t(entry_at) << 32) | id);
        insert_sorted(events.exits, exit_count, (std::uint64_t(exit_at) << 32) | (id + 1u));
    }
    // The two runs merged (each ends at a sentinel above every key), each event dealt to the lanes that
    // have it, in that order: lane l's k-th event in slot k. A lane without it writes `none` into its
    // next slot, which its next event overwrites.
    events.entries[entry_count] = events.exits[exit_count] = ~std::uint64_t(0);
    const int total = entry_count + exit_count;
    Int8 count{};
    for (int e = 0, i = 0, j = 0; e < total; ++e) {
        const std::uint64_t next = events.entries[i] < events.exits[j] ? events.entries[i++] : events.exits[j++];
        const std::uint32_t id = std::uint32_t(next);
        const int n = spheres.by_rank[id >> 1];
        const Int8 has = events.taken[n];
        const Uint8 key = has ? ((id & 1u) ? events.exit[n] : events.entry[n]) : none;
        for (int l = 0; l < 8; ++l) {
            events.key[count[l]][l] = key[l];
            events.id[count[l]][l] = id;
        }
        count -= has;  // has is -1 where the lane has the event
    }
    int slots = 0;
    for (int l = 0; l < 8; ++l) slots = count[l] > slots ? count[l] : slots;
    for (int k = 0; k < slots; ++k) events.key[k] = Int8{} + k < count ? events.key[k] : none;
    // Each lane's events put in its own order: odd-even transposition, a compare-exchange of every
    // neighbouring pair a pass, alternately from the first slot and the second. The slots past a
    // lane's events hold `none`, above every key, and stay behind them.
    for (int pass = 0; pass < kOrderPasses; ++pass)
        for (int k = pass & 1; k + 1 < slots; k += 2) {
            const Uint8 ka = events.key[k], kb = events.key[k + 1], ia = events.id[k], ib = events.id[k + 1];
            const Int8 swap = (kb < ka) | ((kb == ka) & (ib < ia));
            events.key[k] = swap ? kb : ka;
            events.key[k + 1] = swap ? ka : kb;
            events.id[k] = swap ? ib : ia;
            events.id[k + 1] = swap ? ia : ib;
        }
    // Each lane's check: its keys strictly increase (distance bits, then id).
    failed = Int8{};
    for (int k = 1; k < slots; ++k) {
        const Uint8 ka = events.key[k - 1], kb = events.key[k], ia = events.id[k - 1], ib = events.id[k];
        const Int8 after = (kb > ka) | ((kb == ka) & (ib > ia));
        failed |= (Int8{} + k < count) & ~after;
    }

    // Front to back, as packet::walk, each lane's media gathered by the rank of its event's sphere.
    Result out;
    out.transmittance = zero + 1.0f;
    LaneSums media;
    Float8 t_prev{};
    Int8 inside{}, stopped{};
    int walked = 0;  // the slots walked
    for (int k = 0; k < slots; ++k) {
        const Int8 live = (Int8{} + k < count) & ~stopped & ~failed;
        // No lane has an event left: neither has it in a later slot.
        if (!any(live)) break;
        walked = k + 1;
        const Int8 step = walk_segment<kLight>(k, Float8(events.key[k]), live, inside, media.value, rays, min_transmittance,
                                               out, t_prev, stopped, lit_steps);
        // A lane past its events reads rank 0's media and keeps its sums (step is 0 there). Most steps
        // take one sphere in every lane that steps (where the lanes' orders agree and none skipped a
        // sphere the others meet): its media then by one load each, not by gathers.
        const Uint8 id = events.id[k];
        const Int8 rank = step ? Int8(id >> 1u) : Int8{};
        const std::uint32_t first_id = id[__builtin_ctz(unsigned(simd_mask(step)) | 0x100u) & 7];
        const bool uniform = !any(step & (Int8(id) != int(first_id)));
        const int first_rank = int(first_id >> 1u);
        step_media<kLight>(media, inside, step, Int8(id & 1u), spheres.emits, [&](Quantity q) {
            const float* table = media_table(spheres, q);
            return uniform ? zero + table[first_rank] : gather.one(table, rank);
        });
    }
    out.stopped = stopped;
    if constexpr (kLight == Light::kAccurate) lit_steps.steps = walked;
    return out;
}

}  // namespace brume::packet
