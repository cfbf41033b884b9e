#version 460
// peel dual, last: the front layers, then the tail (layers no pass reached), then the back layers,
// then what lies behind. The tail is everything the tail pass summed minus what the composites peeled,
// composited as one homogeneous slab: optical depth X = sum of x, colour the x-weighted mean of its
// layers' colours (the extinction-weighted albedo of docs/methods.md's light model), so it adds
// mean * (1 - exp(-X)) and passes exp(-X) of what lies behind. Its transmittance is exact; its
// colour is exact when the tail's layers share one colour. (Subtracting costs at most float
// rounding of the peeled sums, damped by the transmittance in front of them.)
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "medium.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(set = 0, binding = BINDING_PEEL_STATE, rgba32f) uniform readonly image2D state_image;  // (-near, far, fcur, bcur)
layout(set = 0, binding = BINDING_PEEL_TAIL, rgba32f) uniform readonly image2D tail_image;   // sum (x c, x) of all
layout(set = 0, binding = BINDING_PEEL_ACCUM, std430) readonly buffer AccumBlock { vec4 accum[]; };

layout(location = 0) flat in uint v_pass;  // unused
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint pixel = uint(px.y) * frame.counts.x + uint(px.x);
    vec4 front = accum[3u * pixel], back = accum[3u * pixel + 1u], peeled = accum[3u * pixel + 2u];
    // Layers may remain only where the state is not empty; where no tail was drawn its sums are 0.
    vec4 state = imageLoad(state_image, px);
    vec4 tail = -state.x <= state.y ? max(imageLoad(tail_image, px) - peeled, vec4(0.0)) : vec4(0.0);
    float e = exp(-tail.a);
    vec3 behind = back.rgb + back.a * imageLoad(opaque_image, px).rgb;
    out_radiance = vec4(front.rgb + front.a * (tail.rgb * one_minus_exp_over_x(tail.a, e) + e * behind), 1.0);
}
