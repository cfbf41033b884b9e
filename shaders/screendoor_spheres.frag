#version 460
// screendoor, pass 1 (at S x the image's resolution): each sphere is opaque geometry, kept at this
// sub-sample when its alpha (sphere_sample.glsl: the chord clipped by the eye and the opaque surface)
// exceeds its mask's threshold here, and depth tested by its entry distance, nearest wins.
//
// The mask is fixed to the particle (object space, as in Sen, Chemudugunta & Gopi, "Silhouette-Opaque
// Transparency Rendering"): a random binary texture on the particle's camera-facing plane through its
// centre, with texels one sub-sample footprint wide at the particle's distance (the scale rule of the
// paper's section 4.2.1), so the sub-sample rays cross about one texel each. Texel thresholds are
// hashed from (particle index, texel): the pattern moves with the particle, and different particles'
// masks are independent, so two layers of alpha 0.5 cover 0.75 of a pixel on average, not 0.5 or 1 as
// one shared screen-space mask would.
// A sphere reaching the eye plane has no such plane in front of the eye; it hashes its screen
// sub-sample instead.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "sphere_sample.glsl"

layout(constant_id = 0) const uint S = 4;  // sub-samples per pixel along each axis
layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_color;

// Jarzynski & Olano 2020, "Hash Functions for GPU Rendering": pcg3d, good statistics for
// neighbouring integer inputs.
uvec3 pcg3d(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

// The particle's mask threshold, in [0, 1), where this sub-sample's ray crosses the mask.
float mask_threshold() {
    vec3 offset = v_offset_r2.xyz;                    // eye - centre
    float depth = -dot(offset, frame.forward.xyz);   // the centre's distance along the view
    ivec2 texel;
    if (depth > sqrt(v_offset_r2.w)) {
        // The ray scaled to unit view depth meets the plane at depth `depth`; the plane's axes are the
        // camera's right and up. One sub-sample at unit depth spans 2 tan(fov/2) / (height * S).
        vec3 q = offset + depth * (v_ray / dot(v_ray, frame.forward.xyz));
        vec2 uv = vec2(dot(q, frame.right.xyz) / frame.right.w, dot(q, frame.up.xyz) / frame.up.w);
        float texel_size = depth * 2.0 * frame.up.w / (float(frame.counts.y) * float(S));
        texel = ivec2(floor(uv / texel_size));
    } else {
        texel = ivec2(gl_FragCoord.xy);
    }
    return float(pcg3d(uvec3(uvec2(texel), v_sphere)).x >> 8u) * (1.0 / 16777216.0);
}

void main() {
    SphereSample s;
    float t_opaque = imageLoad(opaque_image, ivec2(gl_FragCoord.xy) / int(S)).a;  // the pixel's opaque surface
    if (!sample_sphere(v_sphere, v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), t_opaque, s)) discard;
    if (!(s.alpha > mask_threshold())) discard;
    out_color = vec4(s.color, 1.0);
    gl_FragDepth = 1.0 / (1.0 + s.t0);  // nearer is larger, as in the opaque pass
}
