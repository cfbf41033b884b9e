#version 460
// ppll, pass 2: sort each pixel's events and integrate the intersecting homogeneous media exactly
// (GUIDE section 1), front to back from the eye.
//
// Lists of any length resolve exactly: the events are consumed in windows of WINDOW. Each window is
// the WINDOW smallest (distance, id) keys greater than the last key already integrated, gathered by
// one walk of the list with an insertion into a sorted local array. A list that fits (the usual case)
// takes one walk, i.e. an insertion sort; a longer one takes ceil(2n / WINDOW) walks and no memory
// beyond the window. Keys are unique (id = sphere * 2 + is_exit), so no event is taken twice or lost.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "bindings.glsl"
#include "rays.glsl"
#include "medium.glsl"
#include "ppll_storage.glsl"

layout(constant_id = 0) const uint WINDOW = 64;
layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(location = 0) out vec4 out_radiance;

// Distances are >= +0.0, so their bit patterns order like the floats.
bool key_less(uvec2 a, uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

void main() {
    if (gl_HelperInvocation) return;
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint head = heads[uint(px.y) * frame.counts.x + uint(px.x)];
    vec4 opaque = imageLoad(opaque_image, px);  // rgb: what lies behind the media, a: its distance
    vec3 dir = pixel_ray_direction(gl_FragCoord.xy);
    vec3 source = source_radiance(dir);

    vec3 radiance = vec3(0.0);
    float transmittance = 1.0;
    bool stopped = false;
    uint list_length = 0u, windows = 0u;

    if (head != LIST_END) {
        uvec2 window[WINDOW];
        uvec2 last = uvec2(0u);
        float sigma_t = 0.0;       // running extinction of the media the ray is in
        vec3 sigma_s = vec3(0.0);  // running scattering coefficient (tau * albedo summed)
        int inside = 0;  // how many media the ray is in
        float t_prev = 0.0;
        for (;;) {
            uint n = 0u;
            for (uint node = head; node != LIST_END;) {
                uvec4 v = load_node(node);
                if (windows == 0u) ++list_length;
                for (uint e = 0u; e < 2u; ++e) {
                    uvec2 key = uvec2(e == 0u ? v.x : v.y, v.z * 2u + e);
                    if (windows > 0u && !key_less(last, key)) continue;  // integrated already
                    if (n == WINDOW) {
                        if (!key_less(key, window[WINDOW - 1u])) continue;
                        n = WINDOW - 1u;  // the largest key drops out; a later window takes it
                    }
                    uint j = n;
                    for (; j > 0u && key_less(key, window[j - 1u]); --j) window[j] = window[j - 1u];
                    window[j] = key;
                    ++n;
                }
                node = v.w;
            }
            ++windows;
            for (uint k = 0u; k < n; ++k) {
                float t = uintBitsToFloat(window[k].x);
                float len = t - t_prev;
                if (len > 0.0) {
                    float x = sigma_t * len;
                    radiance += transmittance * sigma_s * source * (len * one_minus_exp_over_x(x));
                    transmittance *= exp(-x);
                    if (transmittance < frame.params.x) {
                        stopped = true;
                        break;
                    }
                }
                GpuSphere s = spheres[window[k].y >> 1u];
                float tau = s.albedo_extinction.w;
                vec3 tau_albedo = tau * s.albedo_extinction.rgb;
                if ((window[k].y & 1u) == 0u) {
                    sigma_t += tau;
                    sigma_s += tau_albedo;
                    ++inside;
                } else if (--inside == 0) {
                    sigma_t = 0.0;  // back in free space: drop the rounding left by add/subtract
                    sigma_s = vec3(0.0);
                } else {
                    sigma_t = max(sigma_t - tau, 0.0);
                    sigma_s = max(sigma_s - tau_albedo, vec3(0.0));
                }
                t_prev = t;
            }
            if (stopped || n < WINDOW) break;
            last = window[WINDOW - 1u];
        }
    }
    if (!stopped) radiance += transmittance * opaque.rgb;
    out_radiance = vec4(radiance, 1.0);

    // Statistics, one atomic per subgroup.
    uint longest = subgroupMax(list_length);
    uint nonempty = subgroupAdd(list_length > 0u ? 1u : 0u);
    uint long_lists = subgroupAdd(windows > 1u ? 1u : 0u);
    if (subgroupElect()) {
        atomicMax(counters.max_length, longest);
        atomicAdd(counters.nonempty_pixels, nonempty);
        atomicAdd(counters.long_lists, long_lists);
    }
}
