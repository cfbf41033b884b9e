#version 460
// One triangle covering the screen, with the unnormalised pixel ray for noperspective interpolation.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"

layout(location = 0) noperspective out vec3 v_ray;

void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
    v_ray = ndc_ray(p);
}
