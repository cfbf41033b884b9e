#version 460
// tiles: the exact resolve without per-pixel lists (render/methods/tiles.h). One workgroup per
// TILE_SIZE x TILE_SIZE tile; the host lists, per tile, the spheres whose screen rectangle meets it,
// near to far by a lower bound of each sphere's ray distances (its nearest possible distance, less a
// float margin). Each pixel intersects its ray with those spheres in that order and integrates the
// media exactly (the light model of docs/accuracy.md, exact_integrator.glsl).
//
// Every event of a later sphere lies at or past that sphere's bound (the watermark), so when a
// sphere arrives, every pending event before its bound is final and is integrated at once. Pending
// entries wait in one small sorted window, the exits of the media the ray is inside in another
// (tile_windows.glsl): an entry moves its exit into the second window when it is integrated. The
// next event is always the smaller of the two windows' first slots.
//
// When the entry window is full, its first event is integrated before it is final (forced). That
// is checked: an entry that arrives before the last event integrated means the order was wrong.
// After an early stop that followed a forced step, the spheres up to the last event integrated are
// still checked. When more media overlap than the exit window holds, or the order was wrong, the
// pixel is resolved again from the start by the general path: walks of the tile's spheres, each
// keeping the WINDOW smallest events after the last one integrated (event_window.glsl), exact for
// any overlap. So the result never rests on the order being right, and the ordered path costs
// O(n (TILE_PENDING + TILE_OPEN)) for the n spheres of a tile.
//
// lavapipe ends a shader's loops after 65,535 iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS, one
// count for every loop of an 8-lane group, and more than one per iteration of a loop that holds
// others). The compiler cannot see that exit: a flag set before a loop's only break reads as set
// after the loop even when the device cut it. So the shader ends with a probe: a loop of
// frame.pool.z (2) iterations, a count from a uniform that the compiler cannot know. Once the
// device's count has run out, every loop stops after its first iteration, so a probe that stopped
// short means some loop of this group was cut: those pixels are counted in `unresolved`, and the
// host refuses the frame instead of writing it wrong. The scan below holds no inner loop, so a tile
// costs the device about two iterations per sphere.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_vote : require
#define BRUME_NO_FRAGMENT_RAY
#include "bindings.glsl"
#include "medium.glsl"
#include "exact_integrator.glsl"
#include "event_window.glsl"
#include "tile_windows.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_COUNTERS, std430) coherent buffer CounterBlock { ListCounters counters; };
layout(set = 0, binding = BINDING_TILE_FIRST, std430) readonly buffer TileFirstBlock { uint tile_first[]; };
layout(set = 0, binding = BINDING_TILE_ENTRIES, std430) readonly buffer TileEntryBlock { uvec2 tile_entries[]; };
layout(set = 0, binding = BINDING_RADIANCE_BUFFER, std430) writeonly buffer RadianceBufferBlock { vec4 result[]; };

// The ray's visible interval through a sphere: entry clamped to the eye, exit to the opaque surface.
bool visible_interval(vec3 eye, vec3 dir, uint sphere, float limit, out float t0, out float t1) {
    vec4 cr = spheres[sphere].center_radius;
    if (!intersect_sphere(eye - cr.xyz, cr.w * cr.w, dir, t0, t1)) return false;
    t0 = t0 > 0.0 ? t0 : 0.0;  // written so, never max(): the general path compares distances as bits
    t1 = min(t1, limit);
    return t1 > t0;
}

// Spheres taken between two phases of integration (see the scan below), and the integration steps
// of a phase: two events per sphere.
const uint EMIT_EVERY = 2u;

// Integrates the earlier of the two windows' first events; an integrated entry opens its exit.
#define TILE_EMIT                                                                                  \
    {                                                                                              \
        bool from_pending = pt[0] <= xt[0];                                                        \
        float t = from_pending ? pt[0] : xt[0];                                                    \
        uint s = from_pending ? ps[0] : xs[0];                                                     \
        float t_exit = pe[0];                                                                      \
        integrate_event(it, source, uvec2(floatBitsToUint(t), s * 2u + (from_pending ? 0u : 1u))); \
        last_t = t;                                                                                \
        if (from_pending) {                                                                        \
            TILE_PENDING_SHIFT_LEFT                                                                \
            if (xt[TILE_OPEN - 1u] != NO_T) overflow = true;                                       \
            TILE_OPEN_INSERT(t_exit, s)                                                            \
        } else {                                                                                   \
            TILE_OPEN_SHIFT_LEFT                                                                   \
        }                                                                                          \
    }

// One step of a phase: the first pending event, if it is final (before the watermark `mark`). A
// uniform branch: a group with nothing final jumps over it.
#define TILE_EMIT_FINAL                                                                            \
    {                                                                                              \
        bool final_event = !overflow && !it.stopped && min(pt[0], xt[0]) < mark;                   \
        if (subgroupAny(final_event)) if (final_event) TILE_EMIT                                   \
    }

void main() {
    uvec2 gid = gl_GlobalInvocationID.xy;
    bool in_image = gid.x < frame.counts.x && gid.y < frame.counts.y;
    ivec2 px = ivec2(min(gid, frame.counts.xy - 1u));  // lanes past the edge shadow a pixel, write nothing
    uint tile = gl_WorkGroupID.y * frame.pool.x + gl_WorkGroupID.x;
    uint first = tile_first[tile], end = tile_first[tile + 1u];
    vec4 opaque = imageLoad(opaque_image, px);  // rgb: what lies behind the media, a: its distance
    float limit = opaque.a;
    vec3 eye = frame.eye.xyz;
    vec3 dir = pixel_ray_direction(vec2(px) + 0.5);
    vec3 source = source_radiance(dir);
    Integrator it = start_integrator(eye, dir, limit);

    // The ordered path.
    float pt[TILE_PENDING], pe[TILE_PENDING];
    uint ps[TILE_PENDING];
    float xt[TILE_OPEN];
    uint xs[TILE_OPEN];
    TILE_PENDING_CLEAR
    TILE_OPEN_CLEAR
    bool overflow = false, forced = false, in_order = true;
    float last_t = 0.0;  // the last event integrated
    uint hits = 0u, i = first;
    // The host ends the entries with a sentinel whose bound is past every distance, so the entry at
    // a tile's end can always be read.
    for (bool scanning = in_image; scanning; ++i) {
        uvec2 entry = tile_entries[i];  // the same for every lane of the tile: one broadcast read
        // Past the last sphere, or past the opaque surface: every event left is final (the drain).
        if (i >= end || uintBitsToFloat(entry.y) >= limit) break;
        // Events before the watermark are final. They are integrated in phases, every EMIT_EVERY
        // spheres or when a pending window fills up, so that the lanes of a group integrate theirs
        // side by side; a final event may wait for a later phase.
        float mark = uintBitsToFloat(entry.y);
        if ((i - first) % EMIT_EVERY == 0u || subgroupAny(pt[TILE_PENDING - 2u * EMIT_EVERY] != NO_T)) {
            TILE_EMIT_FINAL
            TILE_EMIT_FINAL
            TILE_EMIT_FINAL
            TILE_EMIT_FINAL
        }
        if (overflow || it.stopped) break;
        float t0, t1;
        bool hit = visible_interval(eye, dir, entry.x, limit, t0, t1);
        // Most spheres of a tile miss a given row of it.
        if (subgroupAny(hit)) if (hit) {
            ++hits;
            // No room: integrate the first event before it is final (forced; the check below
            // proves it). If that was an exit, the window is still full: the general path.
            if (pt[TILE_PENDING - 1u] != NO_T) {
                forced = true;
                TILE_EMIT
                if (pt[TILE_PENDING - 1u] != NO_T) overflow = true;
            }
            if (t0 < last_t) in_order = false;  // only possible after a forced step
            TILE_PENDING_INSERT(t0, t1, entry.x)
        }
    }
    // After an early stop that followed a forced step, the order is proven only up to the last
    // event integrated: a sphere further on with an entry before it would have changed the answer.
    for (bool checking = forced && it.stopped && in_order && !overflow; checking; ++i) {
        uvec2 entry = tile_entries[i];
        float t0, t1;
        if (i >= end || uintBitsToFloat(entry.y) > last_t) break;
        if (visible_interval(eye, dir, entry.x, limit, t0, t1) && t0 < last_t) in_order = false;
        checking = in_order;
    }
    // The drain: every event left, in order.
    while (!overflow && !it.stopped && min(pt[0], xt[0]) != NO_T) TILE_EMIT
    bool general = in_image && (overflow || !in_order);

    // The general path, for the pixels the ordered one could not prove.
    if (subgroupAny(general)) if (general) {
        it = start_integrator(eye, dir, limit);
        uvec2 w[WINDOW];
        uvec2 last_key = uvec2(0u);  // the largest key of the last batch
        hits = 0u;
        for (uint walk = 0u;; ++walk) {
            BRUME_WINDOW_CLEAR
            for (uint j = first;; ++j) {
                uvec2 entry = tile_entries[j];
                float mark = uintBitsToFloat(entry.y);
                // A full batch takes nothing from spheres that begin past its last key.
                if (j >= end || mark >= limit || (w[WINDOW - 1u] != NO_KEY && mark > uintBitsToFloat(w[WINDOW - 1u].x)))
                    break;
                float t0, t1;
                if (!visible_interval(eye, dir, entry.x, limit, t0, t1)) continue;
                if (walk == 0u) ++hits;
                uvec2 k_entry = uvec2(floatBitsToUint(t0), entry.x * 2u);
                uvec2 k_exit = uvec2(floatBitsToUint(t1), entry.x * 2u + 1u);
                if (walk == 0u || key_less(last_key, k_entry)) BRUME_WINDOW_INSERT(k_entry)
                if (walk == 0u || key_less(last_key, k_exit)) BRUME_WINDOW_INSERT(k_exit)
            }
            bool full = w[WINDOW - 1u] != NO_KEY;
            last_key = w[WINDOW - 1u];
            while (!it.stopped && w[0] != NO_KEY) {
                integrate_event(it, source, w[0]);
                BRUME_WINDOW_SHIFT_LEFT
            }
            if (!full || it.stopped) break;
        }
    }

    // The probe (see the top of this file): frame.pool.z iterations unless the device's count ran out.
    uint probe = 0u;
    while (probe < frame.pool.z) ++probe;
    bool cut = in_image && probe != frame.pool.z;

    if (!it.stopped) it.radiance += it.transmittance * opaque.rgb;
    if (in_image) result[uint(px.y) * frame.counts.x + uint(px.x)] = vec4(it.radiance, 1.0);

    // Every figure one atomic per subgroup. A pixel whose loops were cut is wrong: always counted.
    uint unresolved = subgroupAdd(cut ? 1u : 0u);
    uint fragments = subgroupAdd(in_image ? hits : 0u);
    if (subgroupElect()) {
        if (unresolved > 0u) atomicAdd(counters.unresolved, unresolved);
        atomicAdd(counters.allocated, fragments);
    }
    if ((frame.pool.w & FRAME_COLLECT_LIST_STATS) == 0u) return;
    uint longest = subgroupMax(in_image ? hits : 0u);
    uint nonempty = subgroupAdd(in_image && hits > 0u ? 1u : 0u);
    uint general_pixels = subgroupAdd(general ? 1u : 0u);
    if (subgroupElect()) {
        atomicMax(counters.max_length, longest);
        atomicAdd(counters.nonempty_pixels, nonempty);
        atomicAdd(counters.long_lists, general_pixels);
    }
}
