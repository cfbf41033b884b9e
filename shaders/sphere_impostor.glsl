// The body of the sphere impostor vertex shaders (sphere_impostor.vert, sphere_impostor_ordered.vert):
// one rectangle per sphere, drawn for the sphere BRUME_INSTANCE_SPHERE. See sphere_impostor.vert.
#ifndef BRUME_SPHERE_IMPOSTOR_GLSL
#define BRUME_SPHERE_IMPOSTOR_GLSL
#define BRUME_VERTEX_STAGE
#include "impostor_interface.glsl"
#include "bindings.glsl"
#include "rays.glsl"
#include "screen_bounds.glsl"

void main() {
    const uint vertex = uint(gl_VertexIndex);
    const uint sphere = BRUME_INSTANCE_SPHERE;
    v_pass = vertex / 6u;
    v_sphere = sphere;
    GpuSphere s = spheres[sphere];
    vec4 rect;
    bool visible = s.albedo_extinction.w > 0.0 && sphere_screen_rect(s.center_radius.xyz, s.center_radius.w, rect);
    gl_Position = visible ? rect_corner(rect, int(vertex % 6u)) : vec4(2.0, 2.0, 0.0, 1.0);
    v_ray = ndc_ray(gl_Position.xy);
    v_offset_r2 = vec4(frame.eye.xyz - s.center_radius.xyz, s.center_radius.w * s.center_radius.w);
}

#endif
