// The exact front-to-back integrator of the light model (docs/accuracy.md): a ray crosses events
// (a sphere's entry or exit, keyed by distance and sphere * 2 + is_exit) in increasing order, and
// between two events the media are homogeneous, so each segment has a closed form. Shared by every
// exact resolve, so that each one differs only in how it orders the events.
#ifndef BRUME_EXACT_INTEGRATOR_GLSL
#define BRUME_EXACT_INTEGRATOR_GLSL

// Front-to-back state of one ray.
struct Integrator {
    vec3 radiance;
    float transmittance;
    float sigma_t;   // running extinction of the media the ray is in
    vec3 sigma_s;    // running scattering coefficient (tau * albedo summed)
    int inside;      // how many media the ray is in
    float t_prev;
    bool stopped;    // transmittance fell below the scene's threshold
};

// Integrates the segment up to the event's distance, then enters or leaves the event's medium.
void integrate_event(inout Integrator it, vec3 source, uvec2 key) {
    float t = uintBitsToFloat(key.x);
    float len = t - it.t_prev;
    if (len > 0.0) {
        float x = it.sigma_t * len;
        float segment_transmittance = exp(-x);
        it.radiance += it.transmittance * it.sigma_s * source * (len * one_minus_exp_over_x(x, segment_transmittance));
        it.transmittance *= segment_transmittance;
        if (it.transmittance < frame.params.x) {
            it.stopped = true;
            return;
        }
    }
    vec4 medium = spheres[key.y >> 1u].albedo_extinction;
    float tau = medium.w;
    vec3 tau_albedo = tau * medium.rgb;
    if ((key.y & 1u) == 0u) {
        it.sigma_t += tau;
        it.sigma_s += tau_albedo;
        ++it.inside;
    } else if (--it.inside == 0) {
        it.sigma_t = 0.0;  // back in free space: drop the rounding left by add/subtract
        it.sigma_s = vec3(0.0);
    } else {
        it.sigma_t = max(it.sigma_t - tau, 0.0);
        it.sigma_s = max(it.sigma_s - tau_albedo, vec3(0.0));
    }
    it.t_prev = t;
}

Integrator start_integrator() { return Integrator(vec3(0.0), 1.0, 0.0, vec3(0.0), 0, 0.0, false); }

#endif
