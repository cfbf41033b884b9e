#version 460
// soft: a spherical billboard (Umenhoffer et al. 2006). The pixel ray's chord through the sphere,
// clipped by the eye and by the opaque surface (sphere_sample.glsl), gives alpha = 1 - exp(-tau *
// chord) and colour albedo * L_s, premultiplied for back-to-front "over" blending.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_color;

void main() {
    SphereSample s;
    float t_opaque = imageLoad(opaque_image, ivec2(gl_FragCoord.xy)).a;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), t_opaque, s)) discard;
    out_color = vec4(s.color * s.alpha, s.alpha);
}
