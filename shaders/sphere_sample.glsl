// One sphere's contribution along one pixel ray, as every method that composites whole spheres
// sees it: the exact chord, clipped to the eye and to the opaque surface, turned into an alpha
// alpha = 1 - exp(-tau * chord) and a colour albedo * L_s + emission (medium.glsl's sphere_color). Methods that cannot express overlapping
// media (sorted, weighted, k-buffer, stochastic, screen-door) all use this, so the comparison is
// about ordering and blending, not about a different light model (docs/methods.md).
// Needs bindings.glsl, rays.glsl and medium.glsl; the impostor varyings come from sphere_impostor.vert.
#ifndef BRUME_SPHERE_SAMPLE_GLSL
#define BRUME_SPHERE_SAMPLE_GLSL

struct SphereSample {
    float t0;      // clipped entry distance (>= 0)
    float t1;      // clipped exit distance (<= opaque distance)
    float alpha;   // 1 - exp(-tau * (t1 - t0))
    vec3 color;    // albedo * L_s + emission: the radiance a fully opaque sphere would show
};

// False when the ray misses the sphere or its clipped chord is empty.
bool sample_sphere(uint sphere, vec3 offset, float r2, vec3 unit_dir, float t_opaque, out SphereSample s) {
    float t0, t1;
    if (!intersect_sphere(offset, r2, unit_dir, t0, t1)) return false;
    s.t0 = t0 > 0.0 ? t0 : 0.0;
    s.t1 = min(t1, t_opaque);
    if (!(s.t1 > s.t0)) return false;
    vec4 medium = spheres[sphere].albedo_extinction;
    float x = medium.w * (s.t1 - s.t0);
    float e = exp(-x);
    s.alpha = x * one_minus_exp_over_x(x, e);  // 1 - e without cancellation for thin spheres
    s.color = sphere_color(sphere, source_radiance(unit_dir));
    return true;
}

#endif
