#version 460
// One impostor rectangle per sphere, read straight from the sphere buffer (no CPU-built mesh):
// instance i draws sphere i as 6 vertices. Spheres without extinction change no pixel and are culled.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "screen_bounds.glsl"

layout(location = 0) flat out uint v_sphere;

void main() {
    v_sphere = gl_InstanceIndex;
    GpuSphere s = spheres[gl_InstanceIndex];
    vec4 rect;
    bool visible = s.albedo_extinction.w > 0.0 && sphere_screen_rect(s.center_radius.xyz, s.center_radius.w, rect);
    gl_Position = visible ? rect_corner(rect, gl_VertexIndex) : vec4(2.0, 2.0, 0.0, 1.0);
}
