#version 460
// peel (classic front-to-back depth peeling, Everitt 2001; Maule, "Survey on Order Independent
// Transparency Techniques", section 3.2), peel pass p.
//
// Each pixel's spheres are ordered by the key (d, sphere) with d = t0 * 2^-k: the clipped entry
// distance of sphere_sample.glsl scaled by a power of two into [0, 1/2] (exact: a power-of-two
// scale only shifts the exponent), d's bits compared as an unsigned integer (d >= +0), the sphere
// index breaking ties. Pass p keeps the fragments whose key is strictly greater than the layer pass
// p-1 peeled (read from the key image that pass wrote) and lets the depth test (LESS on d) keep the
// nearest; among equal d the first in primitive order, the lowest sphere index, survives. So the
// fixed-function test computes exactly the lexicographic minimum of the remaining keys, and
// coincident spheres peel one by one. The winner's key is left in the attachment; the composite
// shades that sphere.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
// x: floatBitsToUint(d), y: sphere; all ones where a pass peeled nothing (no key is greater).
layout(set = 0, binding = BINDING_PEEL_KEYS0, rgba32ui) uniform readonly uimage2D keys0;
layout(set = 0, binding = BINDING_PEEL_KEYS1, rgba32ui) uniform readonly uimage2D keys1;

#include "impostor_interface.glsl"

layout(location = 0) out uvec4 out_key;

const float FLT_MIN_NORMAL = 1.17549435e-38;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SphereSample s;
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), imageLoad(opaque_image, px).a, s))
        discard;
    float d = s.t0 * frame.params.y;
    if (d < FLT_MIN_NORMAL) d = 0.0;  // no denormals: the depth buffer and the key must agree
    uvec2 key = uvec2(floatBitsToUint(d), v_sphere);
    if (v_pass > 0u) {
        // Pass p reads what pass p-1 wrote: keys[p & 1].
        uvec2 prev = ((v_pass & 1u) == 0u ? imageLoad(keys0, px) : imageLoad(keys1, px)).xy;
        if (!(key.x > prev.x || (key.x == prev.x && key.y > prev.y))) discard;  // peeled already
    }
    gl_FragDepth = d;
    out_key = uvec4(key, 0u, 0u);
}
