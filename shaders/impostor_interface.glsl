// The varyings that every sphere pass hands from its vertex shader (sphere_impostor.vert, or
// sorted_particle.glsl for the sorted billboards) to its fragment shader, declared once. A vertex
// shader defines BRUME_VERTEX_STAGE before including this file.
#ifndef BRUME_IMPOSTOR_INTERFACE_GLSL
#define BRUME_IMPOSTOR_INTERFACE_GLSL
#ifdef BRUME_VERTEX_STAGE
#define BRUME_VARYING out
#else
#define BRUME_VARYING in
#endif
layout(location = 0) flat BRUME_VARYING uint v_sphere;        // the sphere's index
layout(location = 1) noperspective BRUME_VARYING vec3 v_ray;  // unnormalised pixel-ray direction (linear on screen)
layout(location = 2) flat BRUME_VARYING vec4 v_offset_r2;     // xyz: eye - centre, w: radius^2
layout(location = 3) flat BRUME_VARYING uint v_pass;          // firstVertex / 6 for multi-pass methods, else 0
#undef BRUME_VARYING
#endif
