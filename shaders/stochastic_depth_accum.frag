#version 460
// stochastic ",depth" variant (Enderton et al. 2010, depth-based stochastic transparency; Maule,
// "Survey on Order Independent Transparency Techniques", section 6.1, steps 4-5), accumulation pass
// over every sphere fragment: its visibility is the fraction of the pixel's S stochastic depth
// samples (layer k: the nearest covering sphere's entry distance, or a huge value where none
// covered) that are NOT in front of it,
//   vis = count(z_k >= t0) / S,
// equality (within a relative 1e-5, since this pass recomputes t0) counting as not in front, so a
// fragment never occludes itself. Target 0 accumulates (alpha vis c, alpha vis), target 1 the
// optical depth sum(tau * chord) for the alpha correction, both additively.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint SAMPLES = 8;  // S: depth layers

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_STOCHASTIC_LAYERS, r32f) uniform readonly image2DArray depth_layers;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_accum;
layout(location = 1) out float out_optical_depth;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, px).a, s))
        discard;
    float limit = s.t0 * (1.0 - 1e-5);
    uint visible = 0u;
    for (uint k = 0u; k < SAMPLES; ++k)
        if (imageLoad(depth_layers, ivec3(px, int(k))).r >= limit) ++visible;
    float w = s.alpha * float(visible) * (1.0 / float(SAMPLES));
    out_accum = vec4(s.color * w, w);
    out_optical_depth = spheres[v_sphere].albedo_extinction.w * (s.t1 - s.t0);
}
