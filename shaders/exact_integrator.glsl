// The exact front-to-back integrator of the light model (docs/accuracy.md): a ray crosses events
// (a sphere's entry or exit, keyed by distance and sphere * 2 + is_exit) in increasing order, and
// between two events the media are homogeneous, so each segment has a closed form. Shared by every
// exact resolve, so that each one differs only in how it orders the events.
//
// `source` is the ray's unshadowed L_s (medium.glsl's source_radiance). Emission and the per-sphere
// shadow technique live here, in running sums beside sigma_t and sigma_s, so a resolve needs no
// change for them: a segment adds T (sigma_s L_ambient + sigma_sun L_sun P + sigma_e) l phi(sigma_t l),
// sigma_sun = sum tau_k albedo_k T_sun(centre_k), sigma_e = sum tau_k e_k. Without shadows
// sigma_sun == sigma_s bit for bit and without emission sigma_e == 0, and the segment is the
// sigma_s * source of the unextended model exactly.
//
// With the accurate shadow technique (frame.params.w = 1) the sun term of a segment is instead
// sigma_s L_sun P times the integral of exp(-sigma_t u) T_sun(x(u)) over it, with the depth toward
// the sun read from the light-space depth map at the ends of short pieces and linear between (a
// closed form, as trace does), box shadows cut out exactly (sun_transmittance.glsl
// find_sun_box_spans); for that the integrator knows its ray and where its opaque surface lies.
// start_integrator(t_opaque) takes the pixel-centre ray of gl_FragCoord (a fragment shader); a resolve
// in another stage defines BRUME_NO_FRAGMENT_RAY and calls start_integrator(eye, dir, t_opaque).
#ifndef BRUME_EXACT_INTEGRATOR_GLSL
#define BRUME_EXACT_INTEGRATOR_GLSL
#include "rays.glsl"
#include "sun_transmittance.glsl"

// Front-to-back state of one ray.
struct Integrator {
    vec3 radiance;
    float transmittance;
    float sigma_t;   // running extinction of the media the ray is in
    vec3 sigma_s;    // running scattering coefficient (tau * albedo summed)
    vec3 sigma_sun;  // the same, each term dimmed by its sphere's T_sun (= sigma_s without shadows)
    vec3 sigma_e;    // running emission (tau * emission summed)
    // Each running sum above is sum + error, stepped as a compensated sum (compensated_step): leaving a
    // dense sphere inside a thin medium gives the thin medium back exactly, not a residue of the dense
    // one's rounding (render/compensated_sum.h; trace's walks keep theirs the same way).
    vec4 ts_sum;     // {sigma_t, sigma_s}
    vec4 ts_error;
    vec4 sun_sum;    // {sigma_sun, 0}: one compensated_step for every sum
    vec4 sun_error;
    vec4 e_sum;      // {sigma_e, 0}
    vec4 e_error;
    int inside;      // how many media the ray is in
    float t_prev;
    bool stopped;    // transmittance fell below the scene's threshold
    vec3 origin;     // the ray, for the accurate shadow technique's samples of T_sun
    vec3 dir;
    // The accurate technique: the optical depth toward the sun at t_prev and exp(-it), when od_valid
    // (kept from the segment before, so each event costs one lookup), and the first box shadow span
    // the ray has not passed.
    float od_prev;
    float sun_prev;
    bool od_valid;
    uint span_next;
};

// With more boxes than SUN_BOX_SPANS (sun_segment_integral's fallback, which each node tests the boxes
// in): the 3-point Gauss-Legendre rule (exact for degree-5 integrands) on the segment, and on two halves
// of a piece longer than SUN_HALVE_CELLS map cells: T_sun has kinks where the segment crosses a shadow
// edge, and a long piece is where a rule straddles them most. Measured with bench shadows at 128x96
// (docs/accuracy.md): one rule per piece left explosion's p99.9 at 1.21e-2; halving every piece,
// 7.6e-3 for 1.5x the frame; halving those over 8 cells, 7.7e-3 within the noise of the frame's time
// (those over 16: 9.9e-3, over 32: unchanged). Each rule costs three reads of the depth map
// (sun_map_depth: eight texels each) and, with many boxes, box tests.
const float SUN_HALVE_CELLS = 8.0;
// 1 when the frame uses the accurate shadow technique. A specialization constant as well as the
// uniform: lavapipe runs the body of an `if` under an empty lane mask even when no lane takes it,
// so the lookups (and their loops, which count against the shader's loop budget) would cost every
// event of every frame without it. Constant 3; the resolve's pipeline is made per technique.
layout(constant_id = 3) const uint ACCURATE_SHADOWS = 0u;
const float GL3_NODE = 0.7745966692414834;
const float GL3_W_OUTER = 0.5555555555555556, GL3_W_CENTRE = 0.8888888888888888;

// T_sun at a quadrature node x = eye + rel: the map's, and 0 where one of the first `boxes` boxes
// blocks the sun. The caller passes 0 boxes when it cut the box shadows out (or there are none): a
// loop that runs no iteration costs nothing on lavapipe, where an `if` or a `?:` between two calls
// runs both bodies under a lane mask (measured: that doubled the lookups and ran the box loop at
// every node of every ray).
float sun_node_transmittance(vec3 x, vec3 rel, uint boxes_to_test) {
    float g = sun_media_map_transmittance(rel);
    vec3 l = -frame.sun_dir.xyz;
    for (uint k = 0u; k < boxes_to_test; ++k) {
        float t;
        if (intersect_box(x, l, boxes[k].min_corner.xyz, boxes[k].max_corner.xyz, t)) {
            g = 0.0;
            break;
        }
    }
    return g;
}

// integral over [u, v] of exp(-sigma_t (t - a)) g(t) dt by one or two Gauss-Legendre rules, g the
// node's T_sun (sun_node_transmittance).
float sun_quadrature(vec3 origin, vec3 dir, float a, float u, float v, float sigma_t, uint boxes_to_test) {
    int pieces = (v - u) * sun_grid.map_origin.w > SUN_HALVE_CELLS ? 2 : 1;
    float h = (v - u) / float(pieces);
    vec3 from_eye = origin - frame.eye.xyz;  // 0 for every resolve's rays: they start at the eye
    float sum = 0.0;
    for (int k = 0; k < pieces; ++k) {
        float m = u + (float(k) + 0.5) * h;
        float tl = m - 0.5 * h * GL3_NODE, tr = m + 0.5 * h * GL3_NODE;
        float gl = sun_node_transmittance(origin + tl * dir, from_eye + tl * dir, boxes_to_test);
        float gm = sun_node_transmittance(origin + m * dir, from_eye + m * dir, boxes_to_test);
        float gr = sun_node_transmittance(origin + tr * dir, from_eye + tr * dir, boxes_to_test);
        sum += GL3_W_OUTER * exp(-sigma_t * (tl - a)) * gl + GL3_W_CENTRE * exp(-sigma_t * (m - a)) * gm +
               GL3_W_OUTER * exp(-sigma_t * (tr - a)) * gr;
    }
    return sum * 0.5 * h;
}

// The spheres' optical depth toward the sun at origin + t dir, from the map (0 without one).
float sun_depth_along(vec3 from_eye, vec3 dir, float t) {
    return sun_grid.map_size.x == 0u ? 0.0 : sun_map_depth(from_eye + t * dir);
}

// integral over [a, b] of exp(-sigma_t (t - a)) T_sun(origin + t dir) dt, the accurate technique with
// trace's pieces and rules (render/fast_tracer.cpp add_sun_pieces, render/sun_jobs.h resolve, which take the
// pieces of a whole tile together after its rays, not one segment at a time): T_sun is 0 inside the ray's box
// shadows (find_sun_box_spans, exact) and exp(-depth) elsewhere, the depth read from the map at the
// ends of pieces no longer than SUN_PIECE_CELLS map cells (in thin media up to SUN_PIECE_THIN_WIDEN
// times that, while sigma_t len stays within SUN_PIECE_THIN_DEPTH; halved, up to SUN_PIECE_SPLITS times,
// where the light the piece may carry, times the share its media scatter, min(1, sigma_t len /
// SUN_PIECE_THIN_DEPTH), times its change of depth exceeds SUN_PIECE_DEPTH_CHANGE) and
// linear between, where the integral has a closed form. The depth and the sun's transmittance at b
// stay in the integrator for the next segment: one lookup per event and one per piece, one
// exponential each, where a 3-point rule took three of each. A segment takes at most
// SUN_MAX_PIECES pieces before halving (longer ones where it is longer), so its loop is bounded.
// With more boxes than SUN_BOX_SPANS (no spans kept) the 3-point rules with each node testing the
// boxes (sun_quadrature) run instead, in a loop of one iteration or none: lavapipe runs no body that
// no lane takes.
// (SUN_PIECE_* and SUN_MAX_PIECES: shaders/shared.h, the CPU's too.)
const float SUN_DIVISIBLE_TRANSMITTANCE = 1e-20;
float sun_segment_integral(inout Integrator it, float a, float b, float sigma_t, float segment_transmittance) {
    bool spans_kept = sun_box_span_count != SUN_BOX_SPANS_NONE;
    uint spans = spans_kept ? sun_box_span_count : 0u;
    uint node_boxes = (frame.params.z != 0.0 && !spans_kept) ? frame.counts.w : 0u;
    float sum = 0.0;
    for (uint once = 0u; once < min(node_boxes, 1u); ++once) {
        sum = sun_quadrature(it.origin, it.dir, a, a, b, sigma_t, node_boxes);
        it.od_valid = false;
    }
    vec3 from_eye = it.origin - frame.eye.xyz;  // 0 for every resolve's rays: they start at the eye
    // The integrand at p, exp(-sigma_t (p - a) - depth(p)), carried from piece to piece.
    float p = a;
    float od_p = it.od_valid ? it.od_prev : sun_depth_along(from_eye, it.dir, a);
    float at_p = it.od_valid ? it.sun_prev : exp(-od_p);
    float inverse_cell = sun_grid.map_size.x == 0u ? 0.0 : sun_grid.map_origin.w;
    float cells = inverse_cell > 0.0 ? SUN_PIECE_CELLS / inverse_cell : 0.0;
    float thin = sigma_t > 0.0 ? SUN_PIECE_THIN_DEPTH / sigma_t : SUN_PIECE_THIN_WIDEN * cells;
    float longest = max(min(thin, SUN_PIECE_THIN_WIDEN * cells), cells);
    float max_piece = inverse_cell > 0.0 ? max(longest, (b - a) / SUN_MAX_PIECES) : b - a;
    float weight = it.transmittance;
    float end = node_boxes == 0u ? b : a;  // the 3-point rules took the segment
    while (p < end) {
        while (it.span_next < spans && sun_box_spans[it.span_next].y <= p) ++it.span_next;
        bool shadowed = it.span_next < spans && sun_box_spans[it.span_next].x <= p;
        float q = min(end, p + max_piece);
        if (it.span_next < spans) q = min(q, shadowed ? sun_box_spans[it.span_next].y : sun_box_spans[it.span_next].x);
        if (!(q > p)) q = end;  // a piece shorter than float's step: end the segment (adds nothing)
        float od_q = sun_depth_along(from_eye, it.dir, q);
        // [p, q], halved where its depth changes fast: the far ends of the halves still to come wait
        // on a stack, nearest last, with their level.
        float wait_t[SUN_PIECE_SPLITS], wait_od[SUN_PIECE_SPLITS];
        int wait_level[SUN_PIECE_SPLITS];
        int waiting = 0, level = 0;
        float r = q, od_r = od_q;
        for (;;) {
            float share = min(sigma_t * (r - p) * (1.0 / SUN_PIECE_THIN_DEPTH), 1.0);
            if (!shadowed && level < SUN_PIECE_SPLITS && weight * at_p * share * abs(od_r - od_p) > SUN_PIECE_DEPTH_CHANGE) {
                wait_t[waiting] = r;
                wait_od[waiting] = od_r;
                wait_level[waiting] = level + 1;
                ++waiting;
                ++level;
                r = 0.5 * (p + r);
                od_r = sun_depth_along(from_eye, it.dir, r);
                continue;
            }
            float len = r - p;
            float x = sigma_t * len + (od_r - od_p);
            // The integrand at r from its own exponent, sigma_t (r - a) + depth(r) >= 0 (as trace's
            // piece_integral8 takes it), not at_p exp(-x): where the depth falls by more than float's
            // exponent holds along one piece (a view ray leaving a very dense sphere's shadow toward the
            // sun), exp(-x) overflows or, clamped, leaves at_p wrong for the rest of the segment
            // (tiles read 7e14 of the peak beside a sphere of extinction 500). Past |x| = 0.125 the
            // piece's integral is the difference of the integrand's ends over x, between the two ends
            // times len however large |x| is; below, the series (one_minus_exp_over_x takes its series
            // for any x under 0.125, so the exponential it is handed is never read).
            float at_r = exp(-(sigma_t * (r - a) + od_r));
            if (!shadowed) {  // in a box's shadow: nothing
                sum += abs(x) < 0.125 ? at_p * len * one_minus_exp_over_x(x, 0.0) : len * ((at_p - at_r) / x);
            }
            at_p = at_r;
            p = r;
            od_p = od_r;
            if (waiting == 0) break;
            --waiting;
            r = wait_t[waiting];
            od_r = wait_od[waiting];
            level = wait_level[waiting];
        }
    }
    if (node_boxes == 0u) {
        it.od_prev = od_p;
        it.od_valid = true;
        // exp(-depth(b)): the integrand at b without the segment's own attenuation, a quotient rather
        // than an exponential; where that attenuation is too deep to divide by, the ray is about to stop.
        it.sun_prev = segment_transmittance > SUN_DIVISIBLE_TRANSMITTANCE ? at_p / segment_transmittance : exp(-od_p);
    }
    return sum;
}

// Integrates the segment up to the event's distance, then enters or leaves the event's medium.
// sum + error += d (render/compensated_sum.h): Knuth's TwoSum keeps the rounding of each step exactly,
// and the errors are summed beside the sum. `precise` keeps a driver from simplifying the rounding's
// expression away, as reassociating it would.
// Leaving a medium clamps a sum below 0 at 0, as the reference does (negative albedos in scenes built
// in code).
void compensated_step(inout vec4 sum, inout vec4 error, vec4 d, bool leaving) {
    precise vec4 s = sum + d;
    precise vec4 d_rounded = s - sum;
    precise vec4 rounding = (sum - (s - d_rounded)) + (d - d_rounded);
    precise vec4 e = error + rounding;
    bvec4 zero = leaving ? lessThan(s + e, vec4(0.0)) : bvec4(false);
    sum = mix(s, vec4(0.0), zero);
    error = mix(e, vec4(0.0), zero);
}

void integrate_event(inout Integrator it, vec3 source, uvec2 key) {
    float t = uintBitsToFloat(key.x);
    float len = t - it.t_prev;
    if (len > 0.0) {
        float x = it.sigma_t * len;
        float segment_transmittance = exp(-x);
        // T sigma_s source, less the sun light the shadows take away (sun P = source - L_ambient), plus
        // emission; grouped so that with neither the sum is T * sigma_s * source, rounded as it always was.
        float w = len * one_minus_exp_over_x(x, segment_transmittance);
        if (ACCURATE_SHADOWS != 0u && frame.params.w != 0.0 && it.inside > 0) {
            // Accurate shadows: ambient and emission in closed form, the sun term by quadrature.
            vec3 sun_phase = source - frame.ambient.rgb;
            float sun = sun_segment_integral(it, it.t_prev, t, it.sigma_t, segment_transmittance);
            it.radiance += it.transmittance * ((it.sigma_s * frame.ambient.rgb + it.sigma_e) * w + it.sigma_s * sun_phase * sun);
        } else {
            vec3 lost = (it.sigma_s - it.sigma_sun) * (source - frame.ambient.rgb) - it.sigma_e;
            it.radiance += (it.transmittance * it.sigma_s * source - it.transmittance * lost) * w;
        }
        it.transmittance *= segment_transmittance;
        if (it.transmittance < frame.params.x) {
            it.stopped = true;
            return;
        }
    }
    if (it.inside == 0) it.od_valid = false;  // free space: the next segment looks its start up
    GpuSphere g = spheres[key.y >> 1u];
    float tau = g.albedo_extinction.w;
    vec3 tau_albedo = tau * g.albedo_extinction.rgb;
    vec3 tau_albedo_sun = tau_albedo * g.emission_sun.w;
    vec3 tau_emission = tau * g.emission_sun.rgb;
    bool entry = (key.y & 1u) == 0u;
    it.inside += entry ? 1 : -1;
    if (it.inside == 0) {
        it.ts_sum = it.ts_error = vec4(0.0);  // back in free space: every sum exactly 0
        it.sun_sum = it.sun_error = it.e_sum = it.e_error = vec4(0.0);
    } else {
        float sign = entry ? 1.0 : -1.0;
        compensated_step(it.ts_sum, it.ts_error, sign * vec4(tau, tau_albedo), !entry);
        compensated_step(it.sun_sum, it.sun_error, vec4(sign * tau_albedo_sun, 0.0), !entry);
        compensated_step(it.e_sum, it.e_error, vec4(sign * tau_emission, 0.0), !entry);
    }
    vec4 ts = it.ts_sum + it.ts_error;
    it.sigma_t = ts.x;
    it.sigma_s = ts.yzw;
    it.sigma_sun = (it.sun_sum + it.sun_error).xyz;
    it.sigma_e = (it.e_sum + it.e_error).xyz;
    it.t_prev = t;
}

// `t_opaque`: the distance to the ray's opaque surface (the opaque image's alpha; +inf where none).
Integrator start_integrator(vec3 origin, vec3 unit_dir, float t_opaque) {
    sun_box_span_count = SUN_BOX_SPANS_NONE;
    if (ACCURATE_SHADOWS != 0u && frame.params.w != 0.0 && frame.params.z != 0.0)
        find_sun_box_spans(origin, unit_dir, t_opaque);
    return Integrator(vec3(0.0), 1.0, 0.0, vec3(0.0), vec3(0.0), vec3(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0),
                      vec4(0.0), vec4(0.0), 0, 0.0, false, origin, unit_dir, 0.0, 1.0, false, 0u);
}

#ifndef BRUME_NO_FRAGMENT_RAY
Integrator start_integrator(float t_opaque) {
    return start_integrator(frame.eye.xyz, pixel_ray_direction(gl_FragCoord.xy), t_opaque);
}
#endif

#endif
