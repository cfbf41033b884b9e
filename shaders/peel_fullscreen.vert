#version 460
// peel: one triangle covering the screen; the pass index rides in the vertex index (firstVertex =
// 3 * pass), so one composite pipeline serves every pass without push constants.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(location = 0) flat out uint v_pass;

void main() {
    uint vertex = uint(gl_VertexIndex);
    v_pass = vertex / 3u;
    int corner = int(vertex % 3u);
    gl_Position = vec4(vec2((corner << 1) & 2, corner & 2) * 2.0 - 1.0, 0.0, 1.0);
}
