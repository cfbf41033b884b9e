#version 460
// kbuf, passes 1 and 2 (docs/methods.md, kbuf): one shader for both, so that both compute
// bit-identical keys for the same fragment.
//   PASS 0: push the fragment's key into the pixel's K sorted slots with an atomicMin chain.
//   PASS 1: claim the slot holding this fragment's key (sphere id by atomicCompSwap, then the exit
//           distance), or, when none is left, add the fragment to the tail targets.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"

layout(constant_id = 0) const uint PASS = 0;
layout(constant_id = 1) const uint K = 8;
const uint EMPTY = 0xffffffffu;

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
// Slot s of pixel p is element p * K + s; keys are sorted ascending within a pixel, EMPTY last.
layout(set = 0, binding = BINDING_KBUF_KEYS, std430) coherent buffer KeyBlock { uint keys[]; };
layout(set = 0, binding = BINDING_KBUF_IDS, std430) coherent buffer IdBlock { uint ids[]; };
layout(set = 0, binding = BINDING_KBUF_EXITS, std430) writeonly buffer ExitBlock { float exits[]; };

#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_tail;             // (alpha c, alpha)
layout(location = 1) out float out_tail_optical_depth;  // tau * chord

// Float bits in an order that unsigned comparison preserves, negative distances included (the
// unclipped entry of a sphere containing the eye is negative). No real distance maps to EMPTY.
uint order_key(float t) {
    uint u = floatBitsToUint(t);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}

void main() {
    if (gl_HelperInvocation) discard;  // helpers have no side effects and must not reach the tail
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 dir = normalize(v_ray);
    float t0, t1;
    if (!intersect_sphere(v_offset_r2.xyz, v_offset_r2.w, dir, t0, t1)) discard;
    float entry = t0 > 0.0 ? t0 : 0.0;
    float exit_distance = min(t1, imageLoad(opaque_image, px).a);
    if (!(exit_distance > entry)) discard;
    uint key = order_key(t0);
    uint base = (uint(px.y) * frame.counts.x + uint(px.x)) * K;

    if (PASS == 0u) {
        // Slots only decrease, and stay sorted: one found <= key (even by a stale plain read) can
        // never take this key, so the chain starts at the first slot above it.
        uint lo = keys[base + K - 1u] <= key ? K : 0u, hi = K;  // most fragments of deep pixels stop here
        while (lo < hi) {
            uint mid = (lo + hi) >> 1u;
            if (keys[base + mid] <= key) lo = mid + 1u;
            else hi = mid;
        }
        uint carry = key;
        for (uint i = lo; i < K; ++i) {
            uint old = atomicMin(keys[base + i], carry);
            carry = max(carry, old);  // the larger of the two moves on
            if (carry == EMPTY) break;
        }
        discard;
    }

    // First slot >= key, then one claim per fragment among the slots equal to it.
    uint lo = keys[base + K - 1u] < key ? K : 0u, hi = K;  // beyond the k-th key: straight to the tail
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (keys[base + mid] < key) lo = mid + 1u;
        else hi = mid;
    }
    bool kept = false;
    for (uint i = lo; i < K; ++i) {
        if (keys[base + i] != key) break;
        if (atomicCompSwap(ids[base + i], EMPTY, v_sphere) == EMPTY) {
            exits[base + i] = exit_distance;
            kept = true;
            break;
        }
    }
    if (kept) discard;
    vec4 medium = spheres[v_sphere].albedo_extinction;
    float x = medium.w * (exit_distance - entry);
    float alpha = x * one_minus_exp_over_x(x, exp(-x));
    out_tail = vec4(sphere_color(v_sphere, source_radiance(dir)) * alpha, alpha);
    out_tail_optical_depth = x;
}
