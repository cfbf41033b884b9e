#version 460
// screendoor, pass 2: box filter of each pixel's S x S sub-samples. A sub-sample where no sphere was
// kept (alpha 0 in the supersampled target) shows the pixel's opaque radiance.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const uint S = 4;
layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_SCREENDOOR_SUBSAMPLES, rgba32f) uniform readonly image2D subsamples;
layout(location = 0) noperspective in vec3 v_ray;  // fullscreen_ray.vert's output, unused here
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    ivec2 base = px * int(S);
    vec4 sum = vec4(0.0);
    for (uint y = 0u; y < S; ++y)
        for (uint x = 0u; x < S; ++x) sum += imageLoad(subsamples, base + ivec2(x, y));
    vec3 behind = imageLoad(opaque_image, px).rgb;
    const float n = float(S * S);
    out_radiance = vec4((sum.rgb + (n - sum.a) * behind) / n, 1.0);
}
