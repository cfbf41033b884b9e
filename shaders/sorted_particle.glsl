// Vertex stage shared by the sorted billboards (`sorted`, `soft`): instance i draws the i-th sphere
// of the back-to-front order, so one instanced draw composites in sorted order (the rasteriser
// blends each pixel's fragments in primitive order). The rectangle is the sphere's conservative
// screen rectangle (screen_bounds.glsl); the fragment shaders decide what is covered. The varyings
// are those of sphere_impostor.vert (impostor_interface.glsl), so sphere_sample.glsl works unchanged.
// Needs bindings.glsl, rays.glsl and screen_bounds.glsl.
#ifndef BRUME_SORTED_PARTICLE_GLSL
#define BRUME_SORTED_PARTICLE_GLSL
#define BRUME_VERTEX_STAGE
#include "impostor_interface.glsl"

layout(set = 0, binding = BINDING_SORT_ORDER, std430) readonly buffer OrderBlock { uint order[]; };

// `planar`: the billboard is the plane through the centre facing the camera, dropped whole when that
// plane lies at or behind the eye.
void emit_sorted_particle(bool planar) {
    uint sphere = order[gl_InstanceIndex];
    v_sphere = sphere;
    v_pass = 0u;  // one pass
    GpuSphere s = spheres[sphere];
    vec4 rect;
    bool visible = s.albedo_extinction.w > 0.0 && sphere_screen_rect(s.center_radius.xyz, s.center_radius.w, rect);
    if (planar) visible = visible && dot(s.center_radius.xyz - frame.eye.xyz, frame.forward.xyz) > 0.0;
    gl_Position = visible ? rect_corner(rect, gl_VertexIndex) : vec4(2.0, 2.0, 0.0, 1.0);
    v_ray = ndc_ray(gl_Position.xy);
    v_offset_r2 = vec4(frame.eye.xyz - s.center_radius.xyz, s.center_radius.w * s.center_radius.w);
}

#endif
