#version 460
// Opaque pass: the exact ray/box hit at the pixel centre (no rasteriser edge snapping), written as
// radiance + distance, with a depth that grows toward the eye so the nearest box wins.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"

layout(location = 0) flat in uint v_box;
layout(location = 0) out vec4 out_radiance_distance;

void main() {
    GpuBox box = boxes[v_box];
    float t;
    if (!intersect_box(frame.eye.xyz, pixel_ray_direction(gl_FragCoord.xy), box.min_corner.xyz,
                       box.max_corner.xyz, t))
        discard;
    out_radiance_distance = vec4(box.radiance.rgb, t);
    // 1/(1+t) keeps float's relative precision at every distance (depth compare GREATER, cleared to 0).
    gl_FragDepth = 1.0 / (1.0 + t);
}
