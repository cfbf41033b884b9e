#version 460
// ppll, pass 2: sort each pixel's events and integrate the intersecting homogeneous media exactly
// (the light model of docs/accuracy.md), front to back from the eye.
//
// Short lists are resolved by the general path below: up to 4 nodes in its first walk, up to 12 in
// at most three.
//
// The ordered path, one walk of the list. The host draws the spheres far to near by a lower bound
// of every distance at which a sphere's ray events can lie (its nearest possible distance, less a
// float margin: ppll.cpp), so the list, built in reverse append order, arrives sorted by that bound.
// When a node arrives, no later node can hold an event before its bound (the watermark), so every
// pending event before it is final and is integrated at once. Pending events wait in a sorted
// window of WINDOW keys in registers (event_window.glsl). Each node takes two emission steps: an
// event below the watermark goes, and so does the smallest one when the window could not take the
// node's two events. A forced emission is only a guess, and so is the order when the device did
// not append fragments in draw order: if a key ever arrives below the last one integrated, the
// order was wrong, and the pixel is resolved again by the general path. So the result is exact
// whatever the order, and the ordered path costs O(n * WINDOW) for a list of n nodes.
//
// The general path: walks of the list, each keeping the WINDOW smallest keys greater than the last
// key integrated, so a list of n nodes takes ceil(2n / WINDOW) walks (O(n^2 / WINDOW)). It runs
// only for pixels where too many media overlap for the window (hundreds of coincident spheres).
//
// lavapipe ends a shader's loops after 65,535 iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS, shared
// by every loop of an invocation). A loop that was cut shows as a list not walked to its end; such a
// pixel is counted in `unresolved`, and the host refuses the frame instead of writing a wrong image.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "bindings.glsl"
#include "medium.glsl"
#include "ppll_storage.glsl"
#include "exact_integrator.glsl"
#include "event_window.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PPLL_BOUNDS, std430) readonly buffer BoundBlock { float nearest_bound[]; };
// 0: every pixel takes the general path (`ppll-general`, the resolve Brume shipped before the
// ordered path: kept to chart what the ordered path gains).
layout(constant_id = 2) const uint ORDERED_PATH = 1u;
layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

// Integrates the window's first event if it lies before the watermark `mark` (final), or if the
// window could not take two more events (forced: checked by the order test).
#define BRUME_EMISSION_STEP                                                        \
    if (!it.stopped && (q[0].x < mark || q[ORDERED_WINDOW - 2u] != NO_KEY)) {      \
        integrate_event(it, source, q[0]);                                         \
        last = q[0];                                                               \
        BRUME_ORDERED_SHIFT_LEFT                                                   \
    }

// The general path's walk over one node: its keys not integrated yet go into the batch.
#define BRUME_GENERAL_TAKE_NODE                                                                   \
    {                                                                                             \
        uvec4 v = load_node(node);                                                                \
        uvec2 entry = uvec2(v.x, v.z * 2u), exit = uvec2(v.y, v.z * 2u + 1u);                     \
        if (walk == 0u || key_less(last_key, entry)) BRUME_WINDOW_INSERT(entry)                   \
        if (walk == 0u || key_less(last_key, exit)) BRUME_WINDOW_INSERT(exit)                     \
        node = v.w;                                                                               \
        ++count;                                                                                  \
    }

// One walk of the general path over the list from `head`: the WINDOW smallest keys after last_key
// (walk 0: of all keys) into w, counting the nodes.
#define BRUME_GENERAL_WALK                                                                        \
    BRUME_WINDOW_CLEAR                                                                            \
    uint count = 0u;                                                                              \
    for (node = head; node != LIST_END;) BRUME_GENERAL_TAKE_NODE

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
    Integrator it = start_integrator(opaque.a);

    // Walk 0 of the general path: it counts the list and keeps its WINDOW smallest events. A list
    // of at most WINDOW / 2 nodes is then complete in registers: short lists (most pixels of light
    // smoke, every pixel of the layers benchmark) need nothing more.
    uvec2 w[WINDOW];
    uvec2 last_key = uvec2(0u);  // the largest key of the general path's last batch
    uint walk = 0u, list_length = 0u, node = head;
    BRUME_GENERAL_WALK
    list_length = count;
    bool cut = node != LIST_END;
    bool general = true, in_order = true;

    // Up to 12 nodes, at most three walks of the general path cost less than the ordered one.
    bool take_ordered = ORDERED_PATH != 0u && !cut && list_length > 12u;
    // A uniform branch (every lane agrees): lavapipe jumps over it, where a divergent `if` runs its
    // body under an empty lane mask. Most subgroups of light smoke have no long list at all.
    if (subgroupBallot(take_ordered) != uvec4(0u)) if (take_ordered) {
        // The ordered path, for longer lists.
        general = false;
        uvec2 q[ORDERED_WINDOW];
        BRUME_ORDERED_CLEAR
        uvec2 last = uvec2(0u);  // the last key integrated
        uint prev_mark = 0u;     // the list must come sorted by bound, or the watermark means nothing
        for (node = head; in_order && node != LIST_END && !it.stopped;) {
            uvec4 v = load_node(node);
            uint mark = floatBitsToUint(max(nearest_bound[v.z], 0.0));
            if (mark < prev_mark) in_order = false;
            prev_mark = mark;
            // Two emission steps: room for this node's two events, and final events leave early.
            BRUME_EMISSION_STEP
            BRUME_EMISSION_STEP
            uvec2 entry = uvec2(v.x, v.z * 2u), exit = uvec2(v.y, v.z * 2u + 1u);  // exit > entry: t1 > t0
            if (entry.x < last.x) in_order = false;  // equal distances may come in any order
            BRUME_ORDERED_INSERT(entry)
            BRUME_ORDERED_INSERT(exit)
            node = v.w;
        }
        // Leaving early out of order is no cut: the general path walks the list again.
        cut = in_order && node != LIST_END && !it.stopped;
        // After an early stop the order is proven only up to the last event integrated: a node
        // further on with an entry before it would have changed the answer (a forced emission may
        // have gone too soon). Nodes come sorted by bound: the check ends at the first bound past it.
        while (in_order && it.stopped && node != LIST_END) {
            uvec4 v = load_node(node);
            uint mark = floatBitsToUint(max(nearest_bound[v.z], 0.0));
            if (mark > last.x) break;
            if (mark < prev_mark || v.x < last.x) in_order = false;
            prev_mark = mark;
            node = v.w;
        }
        while (in_order && !it.stopped && q[0] != NO_KEY) {
            integrate_event(it, source, q[0]);
            BRUME_ORDERED_SHIFT_LEFT
        }
        cut = cut || (in_order && !it.stopped && q[0] != NO_KEY);
        if (!in_order && !cut) {
            // The general path, from the start, where the ordered one could not be sure of the order.
            general = true;
            it = start_integrator(opaque.a);
            BRUME_GENERAL_WALK
            cut = node != LIST_END;
        }
    }

    if (general && !cut) {
        // Batches of the general path: integrate this one, then walk again for the next.
        uint events = 2u * list_length, taken = 0u;
        for (;;) {
            last_key = w[WINDOW - 1u];  // only read when this batch was full
            // Integrate the batch front to back; a loop ends once every lane is done.
            while (!it.stopped && w[0] != NO_KEY) {
                integrate_event(it, source, w[0]);
                BRUME_WINDOW_SHIFT_LEFT
            }
            cut = !it.stopped && w[0] != NO_KEY;
            taken += WINDOW;
            if (cut || it.stopped || taken >= events) break;
            ++walk;
            BRUME_GENERAL_WALK
            cut = node != LIST_END;
            if (cut) break;
        }
    }

    if (!it.stopped) it.radiance += it.transmittance * opaque.rgb;
    out_radiance = vec4(it.radiance, 1.0);

    // A cut loop means the pixel is wrong: always counted (one atomic per subgroup), so the host
    // can refuse the frame. The flag is uniform, so there is no divergence around the ballot.
    uint unresolved = subgroupAdd(cut ? 1u : 0u);
    if (subgroupElect() && unresolved > 0u) atomicAdd(counters.unresolved, unresolved);

    // Statistics on request (the flag is uniform too).
    if ((frame.pool.w & FRAME_COLLECT_LIST_STATS) == 0u) return;
    uint longest = subgroupMax(list_length);
    uint nonempty = subgroupAdd(1u);
    uint general_lists = subgroupAdd(in_order ? 0u : 1u);
    if (subgroupElect()) {
        atomicMax(counters.max_length, longest);
        atomicAdd(counters.nonempty_pixels, nonempty);
        atomicAdd(counters.long_lists, general_lists);
    }
}
