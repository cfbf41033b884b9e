#version 460
// peel: sphere_impostor.vert with the pass index carried in the vertex index. Every peel pass of one
// peel method draws with one pipeline, firstVertex = 6 * pass: the same compiled code computes every
// sphere's entry distance in every pass, so a distance found in one pass compares bit for bit with
// the same sphere's distance in the next (no push constants, no per-pass pipeline that could round
// differently).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "screen_bounds.glsl"

layout(location = 0) flat out uint v_sphere;
layout(location = 1) noperspective out vec3 v_ray;  // unnormalised direction of the pixel ray
layout(location = 2) flat out vec4 v_offset_r2;     // xyz: eye - centre, w: radius^2
layout(location = 3) flat out uint v_pass;          // 0..passes-1: peel passes; passes: the tail

void main() {
    uint vertex = uint(gl_VertexIndex);
    v_pass = vertex / 6u;
    v_sphere = gl_InstanceIndex;
    GpuSphere s = spheres[gl_InstanceIndex];
    vec4 rect;
    bool visible = s.albedo_extinction.w > 0.0 && sphere_screen_rect(s.center_radius.xyz, s.center_radius.w, rect);
    gl_Position = visible ? rect_corner(rect, int(vertex % 6u)) : vec4(2.0, 2.0, 0.0, 1.0);
    v_ray = ndc_ray(gl_Position.xy);
    v_offset_r2 = vec4(frame.eye.xyz - s.center_radius.xyz, s.center_radius.w * s.center_radius.w);
}
