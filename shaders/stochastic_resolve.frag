#version 460
// stochastic, resolve: average the S samples (the layers hold each pass's average) and composite
// over the opaque radiance, plainly or with the alpha correction (docs/methods.md, stochastic).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(constant_id = 0) const uint LAYERS = 2;      // coverage passes
layout(constant_id = 1) const uint CORRECTED = 1u;  // 1: alpha correction, 0: plain average

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_STOCHASTIC_LAYERS, rgba32f) uniform readonly image2DArray layers_image;
layout(set = 0, binding = BINDING_STOCHASTIC_ACCUM, rgba32f) uniform readonly image2D accum_image;
layout(set = 0, binding = BINDING_STOCHASTIC_OPTICAL_DEPTH, r32f) uniform readonly image2D optical_depth_image;

layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 background = imageLoad(opaque_image, px).rgb;
    vec4 sum = vec4(0.0);
    for (uint l = 0u; l < LAYERS; ++l) sum += imageLoad(layers_image, ivec3(px, int(l)));
    // rgb: sum of the covered samples' colours / S; a: covered samples / S.
    vec4 average = sum * (1.0 / float(LAYERS));
    vec3 radiance;
    if (CORRECTED == 0u) {
        radiance = average.rgb + (1.0 - average.a) * background;
    } else {
        float x = min(imageLoad(optical_depth_image, px).r, 1e30);
        float transmitted = exp(-x);
        float alpha_total = x * one_minus_exp_over_x(x, transmitted);
        vec3 color;
        if (average.a > 0.0) {
            color = average.rgb / average.a;
        } else {
            vec4 accum = imageLoad(accum_image, px);  // no sample covered: the alpha-weighted average
            color = accum.a > 0.0 ? accum.rgb / accum.a : vec3(0.0);
        }
        radiance = alpha_total * color + transmitted * background;
    }
    out_radiance = vec4(radiance, 1.0);
}
