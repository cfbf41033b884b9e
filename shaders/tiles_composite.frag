#version 460
// tiles, pass 2: the compute resolve's radiance (tiles_resolve.comp) into the frame's HDR target.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(set = 0, binding = BINDING_TILE_RESULT, std430) readonly buffer TileResultBlock { vec4 result[]; };
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    out_radiance = result[uint(px.y) * frame.counts.x + uint(px.x)];
}
