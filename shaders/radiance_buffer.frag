#version 460
// A frame resolved elsewhere into the frame's HDR target: tiles' compute resolve (tiles_resolve.comp)
// leaves its radiance in a buffer, row by row. (The CPU tracers copy theirs in instead:
// FrameResources::copy_to_hdr.)
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(set = 0, binding = BINDING_RADIANCE_BUFFER, std430) readonly buffer RadianceBufferBlock { vec4 result[]; };
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    out_radiance = result[uint(px.y) * frame.counts.x + uint(px.x)];
}
