#version 460
// peel, the tail pass (drawn only when some pixel may hold layers beyond the last peel pass): every
// sphere the pixel ray meets adds (x * colour, x), x = tau * chord its optical depth (additive
// blending). The resolve subtracts what the composites peeled, leaving the tail; no fragment is
// classified here, so this pipeline need not round like the peel passes.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;

#include "impostor_interface.glsl"

layout(location = 0) out vec4 out_sum;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, px).a, s))
        discard;
    float x = spheres[v_sphere].albedo_extinction.w * (s.t1 - s.t0);
    out_sum = vec4(s.color * x, x);
}
