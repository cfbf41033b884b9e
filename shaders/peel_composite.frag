#version 460
// peel (classic), after peel pass p: shade the sphere the pass peeled (sphere_sample.glsl along the
// pixel ray) and put it under what lies in front: L += T * alpha * colour, T *= exp(-x), x = tau *
// chord (front-to-back "under"; exact for one medium at a time). The optical depth x and x * colour
// of every peeled layer are summed for the tail (peel_resolve.frag). A pixel whose T falls below
// the scene's threshold stops as the reference does: T = 0 (nothing behind counts) and its key
// becomes "nothing left", so later passes peel nothing there. Pixels that peeled a layer and go on
// are counted; when there are any, the next peel pass (or the tail) and its composite are switched
// on in the indirect arguments, so passes beyond the scene's depth draw nothing.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint PASSES = 8;  // peel passes; the tail is geometry pass PASSES

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PEEL_KEYS0, rgba32ui) uniform uimage2D keys0;
layout(set = 0, binding = BINDING_PEEL_KEYS1, rgba32ui) uniform uimage2D keys1;
// Two per pixel: [2 i] = (L, T) front to back, [2 i + 1] = (sum of x * colour, sum of x) peeled.
layout(set = 0, binding = BINDING_PEEL_ACCUM, std430) buffer AccumBlock { vec4 accum[]; };
layout(set = 0, binding = BINDING_PEEL_CONTROL, std430) buffer ControlBlock { PeelControl ctrl; };

layout(location = 0) flat in uint v_pass;

void main() {
    if (gl_HelperInvocation) return;
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint pixel = uint(px.y) * frame.counts.x + uint(px.x);
    uint p = v_pass;
    bool odd = ((p + 1u) & 1u) != 0u;  // pass p wrote keys[(p + 1) & 1]
    uvec2 key = (odd ? imageLoad(keys1, px) : imageLoad(keys0, px)).xy;
    vec4 acc = vec4(0.0, 0.0, 0.0, 1.0), peeled = vec4(0.0);
    if (p > 0u) {
        acc = accum[2u * pixel];
        peeled = accum[2u * pixel + 1u];
    }
    bool go_on = false;
    if (key != uvec2(0xffffffffu)) {
        GpuSphere g = spheres[key.y];
        SphereSample s;
        vec3 offset = frame.eye.xyz - g.center_radius.xyz;
        if (sample_sphere(key.y, offset, g.center_radius.w * g.center_radius.w, pixel_ray_direction(gl_FragCoord.xy),
                          imageLoad(opaque_image, px).a, s)) {
            float x = g.albedo_extinction.w * (s.t1 - s.t0);
            acc.rgb += acc.a * s.alpha * s.color;
            acc.a *= exp(-x);
            peeled += vec4(x * s.color, x);
        }
        if (acc.a < frame.params.x) {
            acc.a = 0.0;  // stopped: nothing behind this layer is added (the reference's early termination)
            if (odd) imageStore(keys1, px, uvec4(0xffffffffu));
            else imageStore(keys0, px, uvec4(0xffffffffu));
        } else {
            go_on = true;
        }
    }
    if (p == 0u || key != uvec2(0xffffffffu)) {
        accum[2u * pixel] = acc;
        accum[2u * pixel + 1u] = peeled;
    }
    uint n = subgroupAdd(go_on ? 1u : 0u);
    if (n > 0u && subgroupElect()) {
        atomicAdd(ctrl.going_on[p], n);
        atomicMax(ctrl.peel_args[p + 1u].y, frame.counts.z);  // next pass (or the tail) draws every sphere
        if (p + 1u < PASSES) atomicMax(ctrl.composite_args[p + 1u].y, 1u);
    }
}
