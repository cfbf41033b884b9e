#version 460
// stochastic, coverage passes: sphere_impostor.vert with the pass number. The pass travels in
// firstVertex (pass p draws vertices 6p .. 6p + 5), since Brume's pipeline layout has no push
// constants; the fragment shader turns it into the pass's sample indices.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "screen_bounds.glsl"

layout(location = 0) flat out uint v_sphere;
layout(location = 1) noperspective out vec3 v_ray;  // unnormalised direction of the pixel ray
layout(location = 2) flat out vec4 v_offset_r2;     // xyz: eye - centre, w: radius^2
layout(location = 3) flat out uint v_pass;

void main() {
    v_sphere = gl_InstanceIndex;
    v_pass = uint(gl_VertexIndex) / 6u;
    GpuSphere s = spheres[gl_InstanceIndex];
    vec4 rect;
    bool visible = s.albedo_extinction.w > 0.0 && sphere_screen_rect(s.center_radius.xyz, s.center_radius.w, rect);
    gl_Position = visible ? rect_corner(rect, gl_VertexIndex % 6) : vec4(2.0, 2.0, 0.0, 1.0);
    v_ray = ndc_ray(gl_Position.xy);
    v_offset_r2 = vec4(frame.eye.xyz - s.center_radius.xyz, s.center_radius.w * s.center_radius.w);
}
