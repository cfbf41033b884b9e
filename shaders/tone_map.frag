#version 460
// A presenter's pass: the linear HDR target to display values, exactly as the PNG writer does
// (render/image_io.cpp): exposure, then the sRGB transfer, clamped to [0, 1], NaN to 0. The target's
// UNORM conversion rounds to the 8-bit code. On an sRGB-format target the hardware encodes instead
// (constant 0 off).
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(constant_id = 0) const bool ENCODE_SRGB = true;

layout(set = 0, binding = BINDING_TONE_MAP_HDR) uniform sampler2D hdr;
layout(push_constant) uniform Params { ToneMapParams params; };

layout(location = 0) out vec4 out_color;

float encode(float linear) {
    float v = linear * params.scale.x;
    v = v > 0.0 ? v : 0.0;  // NaN and negatives: 0
    v = v < 1.0 ? v : 1.0;  // +Inf and overexposure: 1
    if (!ENCODE_SRGB) return v;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

void main() {
    const ivec2 size = ivec2(params.source.zw);
    const vec2 ratio = params.source.xy;
    vec3 c;
    if (ratio == floor(ratio) && all(greaterThanEqual(ratio, vec2(1.0)))) {
        // A whole number of HDR texels per pixel (one when the sizes match; k x k when the scene is
        // supersampled): their mean, as the frame path's readback averages them.
        const ivec2 k = ivec2(ratio);
        const ivec2 first = ivec2(gl_FragCoord.xy) * k;
        c = vec3(0.0);
        for (int b = 0; b < k.y; ++b)
            for (int a = 0; a < k.x; ++a) c += texelFetch(hdr, min(first + ivec2(a, b), size - 1), 0).rgb;
        c /= float(k.x * k.y);
    } else {
        // Nearest texel otherwise.
        const ivec2 texel = min(ivec2(floor(gl_FragCoord.xy * ratio)), size - 1);
        c = texelFetch(hdr, texel, 0).rgb;
    }
    out_color = vec4(encode(c.r), encode(c.g), encode(c.b), 1.0);
}
