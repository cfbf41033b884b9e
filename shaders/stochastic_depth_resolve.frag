#version 460
// stochastic ",depth" variant, resolve: the visibility-weighted average colour
// sum(alpha_i vis_i c_i) / sum(alpha_i vis_i), scaled by the exact total alpha
// alpha_total = 1 - exp(-sum tau chord) (the alpha correction), over the opaque radiance.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_STOCHASTIC_ACCUM, rgba32f) uniform readonly image2D accum_image;
layout(set = 0, binding = BINDING_STOCHASTIC_OPTICAL_DEPTH, r32f) uniform readonly image2D optical_depth_image;

layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 background = imageLoad(opaque_image, px).rgb;
    float x = min(imageLoad(optical_depth_image, px).r, 1e30);
    float transmitted = exp(-x);
    float alpha_total = x * one_minus_exp_over_x(x, transmitted);
    vec4 accum = imageLoad(accum_image, px);
    // The nearest fragment always has vis = 1, so accum.a > 0 wherever any sphere is seen.
    vec3 color = accum.a > 0.0 ? accum.rgb / accum.a : vec3(0.0);
    out_radiance = vec4(alpha_total * color + transmitted * background, 1.0);
}
