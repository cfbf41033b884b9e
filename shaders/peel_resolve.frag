#version 460
// peel (classic), last: the peeled layers, then the tail (layers no pass reached), then what lies
// behind. The tail is everything the tail pass summed minus what the composites peeled,
// composited as one homogeneous slab: optical depth X = sum of x, colour the x-weighted mean of its
// layers' colours (the extinction-weighted albedo of docs/methods.md's light model), so it adds
// mean * (1 - exp(-X)) and passes exp(-X) of what lies behind. Its transmittance is exact; its
// colour is exact when the tail's layers share one colour. (Subtracting costs at most float
// rounding of the peeled sums, damped by the transmittance in front of them.)
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(constant_id = 0) const uint PASSES = 8;  // peel passes

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PEEL_KEYS0, rgba32ui) uniform readonly uimage2D keys0;
layout(set = 0, binding = BINDING_PEEL_KEYS1, rgba32ui) uniform readonly uimage2D keys1;
layout(set = 0, binding = BINDING_PEEL_TAIL, rgba32f) uniform readonly image2D tail_image;  // sum (x c, x) of all
layout(set = 0, binding = BINDING_PEEL_ACCUM, std430) readonly buffer AccumBlock { vec4 accum[]; };

layout(location = 0) flat in uint v_pass;  // unused
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint pixel = uint(px.y) * frame.counts.x + uint(px.x);
    vec4 front = accum[2u * pixel], peeled = accum[2u * pixel + 1u];
    // Layers may remain only where the last pass peeled one (pass PASSES-1 wrote keys[PASSES & 1]).
    // Where no tail was drawn its sums are 0 and nothing is added either way.
    uvec2 key = ((PASSES & 1u) == 0u ? imageLoad(keys0, px) : imageLoad(keys1, px)).xy;
    vec4 tail = key != uvec2(0xffffffffu) ? max(imageLoad(tail_image, px) - peeled, vec4(0.0)) : vec4(0.0);
    float e = exp(-tail.a);
    vec3 behind = imageLoad(opaque_image, px).rgb;
    out_radiance = vec4(front.rgb + front.a * (tail.rgb * one_minus_exp_over_x(tail.a, e) + e * behind), 1.0);
}
