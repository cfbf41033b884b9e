#version 460
// peel dual (dual depth peeling, Bavoil & Myers 2008; Maule, "Survey on Order Independent
// Transparency Techniques", section 3.2), peel pass p.
//
// Keys are (t0, sphere) as in classic peeling (t0: sphere_sample.glsl's clipped entry distance);
// the front peels them in increasing order, the back in decreasing order. Every output is MAX-
// blended (exact: MAX and negation do not round; -inf leaves a channel unchanged), which needs no
// independent blend states. The state each composite leaves for the next pass, per pixel:
//   near, fcur: the front key is the smallest with t0 == near and sphere > fcur;
//   far, bcur:  the back key is the largest with t0 == far and sphere < bcur;
// every key outside [(near, fcur), (far, bcur)] is peeled. Pass p, for each remaining fragment:
//   t0 == near: front group; its smallest and largest sphere index go to `ids`.xy;
//   t0 == far:  back group; its smallest and largest index go to `ids`.zw;
//   near < t0 < far: its t0 goes to `window`, which thus holds the next distinct distances.
// The composite shades the front group's smallest index and the back group's largest (sphere
// indices are exact in float below 2^24), so spheres at one distance peel one by one; without
// such ties each pass peels one front and one back layer. Pass 0 only finds the first window.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PEEL_STATE, rgba32f) uniform readonly image2D state_image;  // (-near, far, fcur, bcur)

#include "impostor_interface.glsl"

layout(location = 0) out vec4 out_window;  // (-t0, t0) of the fragments strictly inside the window
layout(location = 1) out vec4 out_ids;     // (-front index, front index, -back index, back index)

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, px).a, s))
        discard;
    const float NEG_INF = uintBitsToFloat(0xff800000u);
    out_window = vec4(NEG_INF);
    out_ids = vec4(NEG_INF);
    if (v_pass == 0u) {
        out_window.xy = vec2(-s.t0, s.t0);
        return;
    }
    vec4 state = imageLoad(state_image, px);
    float near = -state.x, far = state.y, index = float(v_sphere);
    if (s.t0 < near || (s.t0 == near && index <= state.z)) discard;  // peeled at the front
    if (s.t0 > far || (s.t0 == far && index >= state.w)) discard;    // peeled at the back
    if (s.t0 == near) out_ids.xy = vec2(-index, index);
    if (s.t0 == far) out_ids.zw = vec2(-index, index);
    if (s.t0 > near && s.t0 < far) out_window.xy = vec2(-s.t0, s.t0);
}
