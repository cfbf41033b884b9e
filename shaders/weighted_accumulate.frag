#version 460
// wsum / wavg / wboit, pass 1: every sphere fragment adds its premultiplied colour to the
// accumulation targets (additive blending: the sums cannot depend on draw order). See
// docs/methods.md (wsum, wavg, wboit) for the equations.
//   target 0 (rgba32f): wsum, wavg: (alpha c, alpha);  wboit: w * (alpha c, alpha)
//   target 1 (r32f):    wavg: 1 (the fragment count N);  wsum, wboit: optical depth tau * chord
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint MODE = 0;  // 0 wsum, 1 wavg, 2 wboit (WeightedMode)

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
// x: depth scale D of McGuire & Bavoil's weight (eq. 9), adapted to scene units on the CPU.
layout(set = 0, binding = BINDING_WEIGHT_PARAMS, std430) readonly buffer WeightBlock { WeightParams weight_params; };

#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_accum;
layout(location = 1) out float out_extra;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, px).a, s))
        discard;
    vec4 premultiplied = vec4(s.color * s.alpha, s.alpha);
    float optical_depth = spheres[v_sphere].albedo_extinction.w * (s.t1 - s.t0);
    if (MODE == 2u) {
        // McGuire & Bavoil 2013, eq. 9: w(z, alpha) = alpha * clamp(0.03 / (1e-5 + (z/200)^4), 1e-2, 3e3),
        // with 200 replaced by the scene's D.
        float z = s.t0 / weight_params.depth.x;
        float z2 = z * z;
        float w = s.alpha * clamp(0.03 / (1e-5 + z2 * z2), 1e-2, 3e3);
        out_accum = premultiplied * w;
        out_extra = optical_depth;
    } else {
        out_accum = premultiplied;
        out_extra = MODE == 1u ? 1.0 : optical_depth;
    }
}
