#version 460
// kbuf, pass 3: composite the pixel's slots front to back with "over" (they are sorted by key), stop
// like the reference once transmittance falls below the scene's threshold, then the tail as one
// layer behind them, then the opaque radiance (docs/methods.md, kbuf).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(constant_id = 0) const uint K = 8;
const uint EMPTY = 0xffffffffu;

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_KBUF_KEYS, std430) readonly buffer KeyBlock { uint keys[]; };
layout(set = 0, binding = BINDING_KBUF_IDS, std430) readonly buffer IdBlock { uint ids[]; };
layout(set = 0, binding = BINDING_KBUF_EXITS, std430) readonly buffer ExitBlock { float exits[]; };
layout(set = 0, binding = BINDING_KBUF_TAIL_ACCUM, rgba32f) uniform readonly image2D tail_accum_image;
layout(set = 0, binding = BINDING_KBUF_TAIL_OPTICAL_DEPTH, r32f) uniform readonly image2D tail_optical_depth_image;

layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_radiance;

// Inverse of kbuf_insert.frag's order_key.
float key_distance(uint key) {
    return uintBitsToFloat((key & 0x80000000u) != 0u ? (key & 0x7fffffffu) : ~key);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 background = imageLoad(opaque_image, px).rgb;
    uint base = (uint(px.y) * frame.counts.x + uint(px.x)) * K;
    vec3 source = source_radiance(normalize(v_ray));
    vec3 radiance = vec3(0.0);
    float transmittance = 1.0;
    bool stopped = false;
    for (uint i = 0u; i < K; ++i) {
        uint key = keys[base + i];
        if (key == EMPTY) break;
        uint sphere = ids[base + i];
        if (sphere == EMPTY) continue;  // never claimed (cannot happen: both passes compute the same keys)
        float t0 = key_distance(key);
        float entry = t0 > 0.0 ? t0 : 0.0;
        vec4 medium = spheres[sphere].albedo_extinction;
        float x = medium.w * (exits[base + i] - entry);
        float e = exp(-x);
        // albedo * shadowed source, then emission, grouped so that without either extension the sum is
        // rounded exactly as the unextended model's T * alpha * albedo * source.
        GpuSphere g = spheres[sphere];
        float a = x * one_minus_exp_over_x(x, e);
        radiance += transmittance * a * medium.rgb * shadowed_source(source, g.emission_sun.w) +
                    transmittance * a * g.emission_sun.rgb;
        transmittance *= e;
        if (transmittance < frame.params.x) {
            stopped = true;
            break;
        }
    }
    if (!stopped) {
        float x = min(imageLoad(tail_optical_depth_image, px).r, 1e30);
        if (x > 0.0) {
            vec4 tail = imageLoad(tail_accum_image, px);
            float e = exp(-x);
            vec3 color = tail.a > 0.0 ? tail.rgb / tail.a : vec3(0.0);
            radiance += transmittance * (x * one_minus_exp_over_x(x, e)) * color;
            transmittance *= e;
            stopped = transmittance < frame.params.x;
        }
        if (!stopped) radiance += transmittance * background;
    }
    out_radiance = vec4(radiance, 1.0);
}
