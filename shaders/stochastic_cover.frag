#version 460
// stochastic, coverage pass: the sphere covers each of this pass's samples with probability alpha
// (stratified over all S samples of the pixel, see docs/methods.md, stochastic) and writes its colour
// there; the depth test keeps the nearest covering sphere per sample. With DEPTH_ONLY (the ",depth"
// variant) it writes the sphere's entry distance t0 instead, into an R32F layer.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint SAMPLES = 8;       // S, a power of two
layout(constant_id = 1) const uint PASS_SAMPLES = 4;  // samples per pass (the MSAA sample count)
layout(constant_id = 2) const uint DEPTH_ONLY = 0u;   // 1: write (t0, 0, 0, 0) for the depth-based variant

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_color;

// Jarzynski & Olano 2020, "Hash Functions for GPU Rendering": pcg3d.
uvec3 pcg3d(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    return v;
}

void main() {
    uvec2 px = uvec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, ivec2(px)).a, s))
        discard;
    // Per pixel and sphere, the same in every frame: a random offset xi and a random affine
    // permutation g -> (a g + b) mod S of the sample indices (a odd, so it is a bijection).
    uvec3 h = pcg3d(uvec3(px, v_sphere));
    float xi = float(h.x >> 8u) * (1.0 / 16777216.0);
    uint a = h.y | 1u, b = h.z;
    int mask = 0;
    for (uint j = 0u; j < PASS_SAMPLES; ++j) {
        uint g = v_pass * PASS_SAMPLES + j;
        uint rank = (a * g + b) & (SAMPLES - 1u);
        if ((float(rank) + xi) * (1.0 / float(SAMPLES)) < s.alpha) mask |= 1 << j;
    }
    if (mask == 0) discard;
    gl_SampleMask[0] = mask;
    gl_FragDepth = 1.0 / (1.0 + s.t0);
    out_color = DEPTH_ONLY != 0u ? vec4(s.t0, 0.0, 0.0, 0.0) : vec4(s.color, 1.0);
}
