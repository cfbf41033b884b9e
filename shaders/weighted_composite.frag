#version 460
// wsum / wavg / wboit, pass 2: composite the accumulated layer over the opaque radiance C_bg
// (equations in docs/methods.md, wsum, wavg, wboit).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(constant_id = 0) const uint MODE = 0;  // 0 wsum, 1 wavg, 2 wboit (WeightedMode)

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_WEIGHT_ACCUM, rgba32f) uniform readonly image2D accum_image;
layout(set = 0, binding = BINDING_WEIGHT_EXTRA, r32f) uniform readonly image2D extra_image;

layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

// -log(1 - a) for 0 <= a <= 1, without the cancellation of 1 - a for small a (series below 1/8,
// relative error < a^8 / 9 < 1e-8); +inf at a = 1.
float minus_log_one_minus(float a) {
    if (a < 0.125)
        return a * (1.0 + a * (1.0 / 2.0 + a * (1.0 / 3.0 + a * (1.0 / 4.0 + a * (1.0 / 5.0 + a * (1.0 / 6.0 +
               a * (1.0 / 7.0 + a * (1.0 / 8.0))))))));
    return -log(max(1.0 - a, 0.0));
}

// Coverage 1 - exp(-x) and transmittance exp(-x) of an optical depth x >= 0, exact for small x.
void coverage(float x, out float covered, out float transmitted) {
    x = min(x, 1e30);  // +inf would turn x * (1 - e) / x into NaN
    transmitted = exp(-x);
    covered = x * one_minus_exp_over_x(x, transmitted);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 background = imageLoad(opaque_image, px).rgb;
    vec4 accum = imageLoad(accum_image, px);
    float extra = imageLoad(extra_image, px).r;
    vec3 radiance;
    if (MODE == 0u) {
        // Meshkin: C = sum(alpha c) + C_bg (1 - sum alpha), unclamped.
        radiance = accum.rgb + background * (1.0 - accum.a);
    } else if (MODE == 1u) {
        // Bavoil & Myers: C_avg (1 - (1 - alpha_avg)^N) + C_bg (1 - alpha_avg)^N.
        float n = extra;
        vec3 average = accum.a > 0.0 ? accum.rgb / accum.a : vec3(0.0);
        float alpha_average = n > 0.0 ? min(accum.a / n, 1.0) : 0.0;
        float covered, transmitted;
        coverage(n * minus_log_one_minus(alpha_average), covered, transmitted);
        radiance = average * covered + background * transmitted;
    } else {
        // McGuire & Bavoil: [sum(w alpha c) / sum(w alpha)] (1 - R) + C_bg R, R = prod(1 - alpha) =
        // exp(-sum optical depth).
        vec3 average = accum.a > 0.0 ? accum.rgb / accum.a : vec3(0.0);
        float covered, revealage;
        coverage(extra, covered, revealage);
        radiance = average * covered + background * revealage;
    }
    out_radiance = vec4(radiance, 1.0);
}
