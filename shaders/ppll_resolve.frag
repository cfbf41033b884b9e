#version 460
// ppll, pass 2: sort each pixel's events and integrate the intersecting homogeneous media exactly
// (the light model of docs/methods.md), front to back from the eye.
//
// Events are keyed by (distance, sphere * 2 + is_exit): unique per pixel, so the order is fixed
// whatever order the fragments were appended in. The events are consumed in batches of WINDOW:
// each walk of the list keeps the WINDOW smallest keys greater than the last key integrated, in a
// sorted array held in registers (every index a literal constant: an insertion is a fixed chain of
// compare-and-shift steps). A list of n nodes takes ceil(2n / WINDOW) walks, exact for any length,
// with no per-pixel array in memory. (Dynamically indexed local arrays, as in a textbook insertion
// sort, become per-lane scatters on a CPU device and cost several times more; see docs/performance.md.)
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "bindings.glsl"
#include "medium.glsl"
#include "ppll_storage.glsl"
#include "exact_integrator.glsl"

const uint WINDOW = 8;  // events per walk; BRUME_INSERT and BRUME_SWEEP below are written for 8
const uvec2 NO_KEY = uvec2(0xffffffffu);
layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

// Distances are >= +0.0, so their bit patterns order like the floats.
bool key_less(uvec2 a, uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

void main() {
    if (gl_HelperInvocation) return;
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint head = heads[uint(px.y) * frame.counts.x + uint(px.x)];
    vec4 opaque = imageLoad(opaque_image, px);  // rgb: what lies behind the media, a: its distance
    if (head == LIST_END) {
        out_radiance = vec4(opaque.rgb, 1.0);
        return;  // empty pixels take no part in the statistics below: they add nothing to them
    }
    vec3 source = source_radiance(normalize(v_ray));
    Integrator it = start_integrator();

    uvec2 w[WINDOW];  // the batch, sorted; NO_KEY marks empty slots (it sorts after every real key)
    // Inserts `key` into the sorted batch, dropping the largest: with c_i = (key sorts before slot i),
    // slot i takes its left neighbour if c_(i-1), else key if c_i, else keeps its own. All eight
    // comparisons use the batch as it was, so they are made once, before any slot moves.
#define BRUME_SHIFT(i, c_left, c) w[i] = c_left ? w[i - 1] : (c ? key : w[i]);
#define BRUME_INSERT(k)                                                                           \
    {                                                                                             \
        uvec2 key = k;                                                                            \
        bool c0 = key_less(key, w[0]), c1 = key_less(key, w[1]), c2 = key_less(key, w[2]);       \
        bool c3 = key_less(key, w[3]), c4 = key_less(key, w[4]), c5 = key_less(key, w[5]);       \
        bool c6 = key_less(key, w[6]), c7 = key_less(key, w[7]);                                 \
        BRUME_SHIFT(7, c6, c7) BRUME_SHIFT(6, c5, c6) BRUME_SHIFT(5, c4, c5)                      \
        BRUME_SHIFT(4, c3, c4) BRUME_SHIFT(3, c2, c3) BRUME_SHIFT(2, c1, c2)                      \
        BRUME_SHIFT(1, c0, c1)                                                                    \
        w[0] = c0 ? key : w[0];                                                                   \
    }

    uvec2 last = uvec2(0u);
    uint list_length = 0u, events = 0u, taken = 0u, walks = 0u;
    for (;;) {
        w[0] = w[1] = w[2] = w[3] = w[4] = w[5] = w[6] = w[7] = NO_KEY;
        for (uint node = head; node != LIST_END;) {
            uvec4 v = load_node(node);
            uvec2 entry = uvec2(v.x, v.z * 2u), exit = uvec2(v.y, v.z * 2u + 1u);
            if (walks == 0u) {
                ++list_length;
                BRUME_INSERT(entry)
                BRUME_INSERT(exit)
            } else {
                if (key_less(last, entry)) BRUME_INSERT(entry)  // not integrated yet
                if (key_less(last, exit)) BRUME_INSERT(exit)
            }
            node = v.w;
        }
        if (walks == 0u) events = 2u * list_length;
        ++walks;
        last = w[WINDOW - 1u];  // only read when this batch was full
        // Integrate the batch front to back, shifting it left so the next event is always in
        // slot 0: a loop ends once every lane is done, where unused slots would cost full events.
        while (!it.stopped && w[0] != NO_KEY) {
            integrate_event(it, source, w[0]);
            w[0] = w[1]; w[1] = w[2]; w[2] = w[3]; w[3] = w[4]; w[4] = w[5]; w[5] = w[6]; w[6] = w[7];
            w[7] = NO_KEY;
        }
        taken += WINDOW;
        if (it.stopped || taken >= events) break;
    }
#undef BRUME_INSERT
#undef BRUME_SHIFT

    if (!it.stopped) it.radiance += it.transmittance * opaque.rgb;
    out_radiance = vec4(it.radiance, 1.0);

    // Statistics, one atomic per subgroup, on request (the flag is uniform: no divergence here).
    if ((frame.pool.w & FRAME_COLLECT_LIST_STATS) == 0u) return;
    uint longest = subgroupMax(list_length);
    uint nonempty = subgroupAdd(1u);
    uint long_lists = subgroupAdd(walks > 1u ? 1u : 0u);
    if (subgroupElect()) {
        atomicMax(counters.max_length, longest);
        atomicAdd(counters.nonempty_pixels, nonempty);
        atomicAdd(counters.long_lists, long_lists);
    }
}
