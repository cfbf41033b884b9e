#version 460
// stochastic, total-alpha pass (the alpha correction, eq. 6.1 of Maule, "Survey on Order
// Independent Transparency Techniques"): per pixel sum(alpha c) and sum(alpha) (target 0) and the
// optical depth sum(tau * chord) (target 1), so that alpha_total = 1 - prod(1 - alpha_i) =
// 1 - exp(-sum) without rounding thin spheres away.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_accum;
layout(location = 1) out float out_optical_depth;

void main() {
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray),
                       imageLoad(opaque_image, ivec2(gl_FragCoord.xy)).a, s))
        discard;
    out_accum = vec4(s.color * s.alpha, s.alpha);
    out_optical_depth = spheres[v_sphere].albedo_extinction.w * (s.t1 - s.t0);
}
