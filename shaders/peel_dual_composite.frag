#version 460
// peel dual, after peel pass p (see peel_dual.frag for the state): shade the front group's smallest
// sphere index under the front layers (L_f += T_f * alpha * colour, T_f *= exp(-x)) and the back
// group's largest index in front of the back layers (C_b = alpha * colour + exp(-x) * C_b,
// T_b *= exp(-x)), each with sphere_sample.glsl along the pixel ray; sum x and x * colour of both
// for the tail; then set the state of the next pass. A group with more than one sphere keeps its
// distance and advances its cursor (fcur, bcur), so tied spheres peel one per pass and end. A pixel
// whose T_f falls below the scene's threshold stops as the reference does (T_f = 0, state empty).
// Pixels whose state is not empty are counted and switch on the next pass (or the tail).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint PASSES = 9;  // peel passes including pass 0; the tail is PASSES

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PEEL_STATE, rgba32f) uniform image2D state_image;  // (-near, far, fcur, bcur)
layout(set = 0, binding = BINDING_PEEL_WINDOW, rgba32f) uniform readonly image2D window_image;
layout(set = 0, binding = BINDING_PEEL_IDS, rgba32f) uniform readonly image2D ids_image;
// Three per pixel: (L_f, T_f), (C_b, T_b), (sum of x * colour, sum of x) peeled.
layout(set = 0, binding = BINDING_PEEL_ACCUM, std430) buffer AccumBlock { vec4 accum[]; };
layout(set = 0, binding = BINDING_PEEL_CONTROL, std430) buffer ControlBlock { PeelControl ctrl; };

layout(location = 0) flat in uint v_pass;

const float NO_FRONT = -1.0, NO_BACK = 16777216.0;  // cursors before any index / after every index

// One sphere as a layer along this pixel's ray: rgb alpha * colour, a exp(-x); `sums` gets (x * colour, x).
vec4 layer(uint sphere, vec3 dir, float t_opaque, inout vec4 sums) {
    GpuSphere g = spheres[sphere];
    SphereSample s;
    if (!sample_sphere(sphere, frame.eye.xyz - g.center_radius.xyz, g.center_radius.w * g.center_radius.w, dir,
                       t_opaque, s))
        return vec4(0.0, 0.0, 0.0, 1.0);
    float x = g.albedo_extinction.w * (s.t1 - s.t0);
    sums += vec4(x * s.color, x);
    return vec4(s.alpha * s.color, exp(-x));
}

void main() {
    if (gl_HelperInvocation) return;
    const float INF = uintBitsToFloat(0x7f800000u);
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint pixel = uint(px.y) * frame.counts.x + uint(px.x);
    uint p = v_pass;
    vec4 w = imageLoad(window_image, px);
    float n = -w.x, f = w.y;  // nearest and farthest t0 strictly inside the window (+inf, -inf: none)
    vec4 front = vec4(0.0, 0.0, 0.0, 1.0), back = vec4(0.0, 0.0, 0.0, 1.0), peeled = vec4(0.0);
    float near2 = n, far2 = f, fcur2 = NO_FRONT, bcur2 = NO_BACK;  // the next state
    if (p > 0u) {
        front = accum[3u * pixel];
        back = accum[3u * pixel + 1u];
        peeled = accum[3u * pixel + 2u];
        vec4 state = imageLoad(state_image, px);
        float near = -state.x, far = state.y;
        vec4 ids = imageLoad(ids_image, px);
        float fmin = -ids.x, fmax = ids.y, bmin = -ids.z, bmax = ids.w;
        bool fgroup = fmax >= fmin, bgroup = bmax >= bmin, single = near == far;
        vec3 dir = pixel_ray_direction(gl_FragCoord.xy);
        float t_opaque = imageLoad(opaque_image, px).a;
        if (fgroup) {
            vec4 l = layer(uint(fmin), dir, t_opaque, peeled);
            front.rgb += front.a * l.rgb;
            front.a *= l.a;
        }
        if (bgroup && !(single && bmax == fmin)) {
            vec4 l = layer(uint(bmax), dir, t_opaque, peeled);
            back.rgb = l.rgb + l.a * back.rgb;
            back.a *= l.a;
        }
        if (single) {
            // One distance left: the front took its smallest index, the back its largest; indices
            // strictly between may remain (the next pass finds out).
            bool more = fgroup && bmax > fmin + 1.0;
            near2 = more ? near : INF;
            far2 = more ? far : -INF;
            fcur2 = fmin;
            bcur2 = bmax;
        } else {
            bool front_more = fgroup && fmax > fmin, back_more = bgroup && bmin < bmax, inside = n <= f;
            if (front_more) {
                near2 = near;
                fcur2 = fmin;
            } else {
                near2 = inside ? n : (back_more ? far : INF);
            }
            if (back_more) {
                far2 = far;
                bcur2 = bmax;
            } else {
                far2 = inside ? f : (front_more ? near : -INF);
            }
        }
    }
    bool go_on = near2 <= far2;
    if (front.a < frame.params.x) {
        front.a = 0.0;  // stopped: nothing behind the front layers is added
        go_on = false;
    }
    if (!go_on) {
        near2 = INF;
        far2 = -INF;
    }
    imageStore(state_image, px, vec4(-near2, far2, fcur2, bcur2));
    accum[3u * pixel] = front;
    accum[3u * pixel + 1u] = back;
    accum[3u * pixel + 2u] = peeled;
    uint count = subgroupAdd(go_on ? 1u : 0u);
    if (count > 0u && subgroupElect()) {
        atomicAdd(ctrl.going_on[p], count);
        atomicMax(ctrl.peel_args[p + 1u].y, frame.counts.z);
        if (p + 1u < PASSES) atomicMax(ctrl.composite_args[p + 1u].y, 1u);
    }
}
