// The light model (docs/methods.md) in float: Rayleigh source term and a cancellation-free
// segment integral.
#ifndef BRUME_MEDIUM_GLSL
#define BRUME_MEDIUM_GLSL

// (1 - exp(-x)) / x for x >= 0, given exp_minus_x = exp(-x) (the caller needs it for the
// transmittance too). Below 1/8 the series (error < x^6/5040 < 1e-9) avoids the cancellation of
// 1 - exp(-x); it is 1 at x = 0, so empty space and tau -> 0 need no special case.
float one_minus_exp_over_x(float x, float exp_minus_x) {
    if (x < 0.125)
        return 1.0 - x * 0.5 * (1.0 - x * (1.0 / 3.0) * (1.0 - x * 0.25 * (1.0 - x * 0.2 * (1.0 - x * (1.0 / 6.0)))));
    return (1.0 - exp_minus_x) / x;
}

// L_s = L_ambient + L_sun * 3/(16 pi) * (1 + cos^2 theta), theta between sunlight and view ray.
vec3 source_radiance(vec3 unit_dir) {
    float cos_theta = dot(frame.sun_dir.xyz, unit_dir);
    return frame.ambient.rgb + frame.sun.rgb * (0.05968310365946075 * (1.0 + cos_theta * cos_theta));
}

// A medium's source with its sun term dimmed by t_sun, from the unshadowed source of the ray:
// L_ambient + (source - L_ambient) t_sun, written so that t_sun = 1 gives `source` bit for bit.
vec3 shadowed_source(vec3 source, float t_sun) {
    return source - (1.0 - t_sun) * (source - frame.ambient.rgb);
}

// The radiance a fully opaque sphere of this medium would show along a ray whose unshadowed source is
// `source`: albedo times its (per-sphere shadowed) source, plus its emission. What the methods that
// composite whole spheres blend, so they share the exact methods' light term.
vec3 sphere_color(uint sphere, vec3 source) {
    GpuSphere g = spheres[sphere];
    return g.albedo_extinction.rgb * shadowed_source(source, g.emission_sun.w) + g.emission_sun.rgb;
}

#endif
