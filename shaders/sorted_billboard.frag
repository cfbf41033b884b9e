#version 460
// sorted: a classic planar billboard. The plane passes through the sphere's centre, perpendicular to
// the view direction; at each pixel it shows alpha = 1 - exp(-tau * chord) with the whole chord of
// the sphere along the pixel ray (the sprite's "thickness texture", here computed exactly) and colour
// albedo * L_s, premultiplied for "over" blending. It is depth tested where the plane is: a pixel
// whose opaque surface is nearer than the plane shows nothing of this sphere (a hard cut), one whose
// opaque surface is farther shows the whole chord, even the part behind that surface. The chord is
// not clipped by the eye either (a sphere sprite knows nothing of its own depth extent).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"
layout(location = 0) out vec4 out_color;

void main() {
    vec3 dir = normalize(v_ray);
    float t0, t1;
    if (!intersect_sphere(v_offset_r2.xyz, v_offset_r2.w, dir, t0, t1)) discard;
    // Distance along this ray to the billboard's plane (the vertex stage dropped planes behind the eye).
    float plane_depth = -dot(v_offset_r2.xyz, frame.forward.xyz);
    float t_plane = plane_depth / dot(dir, frame.forward.xyz);
    if (!(t_plane < imageLoad(opaque_image, ivec2(gl_FragCoord.xy)).a)) discard;
    vec4 medium = spheres[v_sphere].albedo_extinction;
    float x = medium.w * (t1 - t0);
    float alpha = x * one_minus_exp_over_x(x, exp(-x));  // 1 - exp(-x) without cancellation
    out_color = vec4(sphere_color(v_sphere, source_radiance(dir)) * alpha, alpha);
}
