// T_sun at a point (docs/accuracy.md, "Light through the smoke"), the float twin of render/sun_light.h:
// 0 if the ray x + s l (s > 0, l toward the sun) meets a box, else exp(-sum_k tau_k len_k(x)). The
// spheres come from the light-space grid (SunGridHeader in shared.h): only those whose shadow disc
// overlaps x's cell. The opaque pass evaluates it once per lit box fragment. In the media, the per-sphere
// technique uses the values in GpuSphere.emission_sun.w, and the accurate one the light-space depth
// map (sun_map_depth below; exact_integrator.glsl integrates it along each segment).
// Needs bindings.glsl and rays.glsl.
#ifndef BRUME_SUN_TRANSMITTANCE_GLSL
#define BRUME_SUN_TRANSMITTANCE_GLSL
#extension GL_EXT_control_flow_attributes : require

// Length of the ray x + s l (s > 0, l unit) inside the sphere (c, r^2); through the whole sphere the
// chord itself, not a difference of roots that cancels far away.
float sun_ray_length_inside(vec3 x, vec3 l, vec3 c, float r2) {
    vec3 oc = x - c;
    float b = dot(oc, l);
    vec3 perp = oc - b * l;
    float disc = r2 - dot(perp, perp);
    if (!(disc > 0.0)) return 0.0;
    float s = sqrt(disc);
    if (-b - s >= 0.0) return 2.0 * s;
    return max(s - b, 0.0);
}

// Whether the ray x + s l (s > 0) toward the sun meets a box: a box's shadow is exact (T_sun = 0) for
// both techniques. `skip_box`: the box x lies on (a ray leaving a convex box through a face it lights
// never re-enters it); any value >= the box count skips none.
bool sun_box_blocked(vec3 x, uint skip_box) {
    vec3 l = -frame.sun_dir.xyz;
    for (uint b = 0u; b < frame.counts.w; ++b) {
        float t;
        if (b != skip_box && intersect_box(x, l, boxes[b].min_corner.xyz, boxes[b].max_corner.xyz, t)) return true;
    }
    return false;
}

float sun_transmittance(vec3 x, uint skip_box) {
    if (frame.params.z == 0.0) return 1.0;
    if (sun_box_blocked(x, skip_box)) return 0.0;
    vec3 l = -frame.sun_dir.xyz;
    uint side = sun_grid.size.x;
    if (side == 0u) return 1.0;
    ivec2 cell = ivec2(floor((vec2(dot(x, sun_grid.u_axis.xyz), dot(x, sun_grid.v_axis.xyz)) -
                              vec2(sun_grid.u_axis.w, sun_grid.v_axis.w)) / sun_grid.cell.x));
    // Outside the grid: outside every listed sphere's shadow cylinder (an empty run of the list).
    bool inside = all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, ivec2(int(side))));
    uint c = inside ? uint(cell.y) * side + uint(cell.x) : 0u;
    uint first = sun_grid_data[c], last = inside ? sun_grid_data[c + 1u] : first;
    uint items = side * side + 1u;  // the sphere list follows the offsets
    float depth = 0.0;
    // The cell lists run from the sun down (render/sun_light.h): once a sphere ends behind x as the sun
    // sees it, dot(c, l) + r <= dot(x, l), it and every later one add nothing. The margin covers float
    // rounding of the two dot products, so no sphere that reaches x is cut.
    float x_end = dot(x, l);
    for (uint n = first; n < last; ++n) {
        GpuSphere g = spheres[sun_grid_data[items + n]];
        float c_end = dot(g.center_radius.xyz, l) + g.center_radius.w;
        if (c_end < x_end - 1e-5 * (abs(x_end) + abs(c_end) + 1.0)) break;
        float tau = g.albedo_extinction.w;
        if (tau > 0.0) depth += tau * sun_ray_length_inside(x, l, g.center_radius.xyz, g.center_radius.w * g.center_radius.w);
    }
    // The outsized spheres, in no cell's list (render/outsized_spheres.h; none in the shipped presets).
    // Not unrolled (here and in sun_outsized_depth): lavapipe's compiler unrolls a loop over a fixed
    // array to the array's length, and those copies, run by no lane, cost the whole resolve around
    // them. With the arrays at 8 (they were 4), ppll's shadowed resolve took 1.2-1.4x its time, tiles'
    // up to 1.7x; not unrolled, 0.62-0.77x and 0.60-0.66x of that (docs/performance.md, seventeenth
    // session).
    [[dont_unroll]] for (uint k = 0u; k < sun_grid.size.w; ++k) {
        GpuSphere g = spheres[sun_grid.grid_outsized[k >> 2u][k & 3u]];
        depth += g.albedo_extinction.w * sun_ray_length_inside(x, l, g.center_radius.xyz, g.center_radius.w * g.center_radius.w);
    }
    return exp(-depth);
}

// The outsized spheres' optical depth above the point g in lattice coordinates (SunGridHeader.outsized):
// each one's chord from the point (or its bottom) to its top, times tau, as the CPU's
// SunDepthMap::outsized_depth.
float sun_outsized_depth(vec3 g) {
    float depth = 0.0;
    [[dont_unroll]] for (uint k = 0u; k < sun_grid.size.z; ++k) {
        vec4 o = sun_grid.outsized[k];
        vec2 d = g.xy - o.xy;
        float h2 = o.w - dot(d, d);
        if (!(h2 > 0.0)) continue;
        float half_chord = sqrt(h2), bottom = o.z - half_chord;
        float from = g.z > bottom ? g.z : bottom;  // NaN: from the bottom, as the CPU's
        depth += sun_grid.outsized_depth[k >> 2u][k & 3u] * max(o.z + half_chord - from, 0.0);
    }
    return depth;
}

// A sparse cloud's spheres' optical depth above the point g in lattice coordinates, exactly: the chords
// of the spheres g's column lists (SunGridHeader.columns), from the sun down until one ends below g, as
// the CPU's SunDepthMap::column_depth. 0 outside the columns (or NaN).
float sun_column_depth(vec3 g) {
    uvec4 n = sun_grid.column_size;
    vec2 c = (g.xy - sun_grid.columns.xy) * sun_grid.columns.z;
    if (!(c.x >= 0.0 && c.y >= 0.0 && c.x < float(n.x) && c.y < float(n.y))) return 0.0;
    uint column = n.z + uint(c.y) * n.x + uint(c.x);
    uint first = sun_grid_data[column], last = sun_grid_data[column + 1u];
    float depth = 0.0;
    for (uint k = first; k < last; ++k) {
        uint w = n.w + k * SUN_COLUMN_WORDS;
        if (uintBitsToFloat(sun_grid_data[w + 5u]) < g.z) break;  // this one and every later one end below g
        vec4 o = vec4(uintBitsToFloat(sun_grid_data[w]), uintBitsToFloat(sun_grid_data[w + 1u]),
                      uintBitsToFloat(sun_grid_data[w + 2u]), uintBitsToFloat(sun_grid_data[w + 3u]));
        vec2 d = g.xy - o.xy;
        float h2 = o.w - dot(d, d);
        if (!(h2 > 0.0)) continue;
        float half_chord = sqrt(h2), bottom = o.z - half_chord;
        float from = g.z > bottom ? g.z : bottom;
        depth += uintBitsToFloat(sun_grid_data[w + 4u]) * max(o.z + half_chord - from, 0.0);
    }
    return depth;
}

// The spheres' optical depth toward the sun at eye + rel, from the accurate technique's light-space
// map (render/sun_depth_map.h; SunGridHeader.map_*): trilinear between vertices that hold it exactly.
// Its cost does not grow with the smoke above the point: eight reads, and a closed form for each
// sphere the map takes whole (the outsized ones, none in the shipped presets; or every sphere of a
// scene of at most SUN_MAX_WHOLE, 48, whose lattice holds only zeros); a sparse cloud's spheres exactly,
// through its columns (sun_column_depth), each column's walk as long as the spheres above the point.
float sun_map_depth(vec3 rel) {
    uvec3 n = sun_grid.map_size.xyz;
    vec3 g = sun_grid.map_origin.xyz +
             vec3(dot(rel, sun_grid.u_axis.xyz), dot(rel, sun_grid.v_axis.xyz), dot(rel, -frame.sun_dir.xyz)) *
                 sun_grid.map_origin.w;
    float outsized = sun_outsized_depth(g);
    if (sun_grid.column_size.x > 0u) return sun_column_depth(g) + outsized;  // a sparse cloud, exactly
    // Outside the lattice's columns (or NaN): outside every shadow cylinder in it.
    if (!(g.x >= 0.0 && g.y >= 0.0 && g.x < float(n.x - 1u) && g.y < float(n.y - 1u))) return outsized;
    g.z = clamp(g.z, 0.0, float(n.z - 1u));  // below the lowest sphere the whole column; above, 0
    uvec3 c = uvec3(g);
    c.z = min(c.z, n.z - 2u);
    vec3 f = g - vec3(c);
    uint base = sun_grid.map_size.w + (c.y * n.x + c.x) * n.z + c.z;
    uint su = n.z, sv = n.x * n.z;
    float a = mix(uintBitsToFloat(sun_grid_data[base]), uintBitsToFloat(sun_grid_data[base + 1u]), f.z);
    float b = mix(uintBitsToFloat(sun_grid_data[base + su]), uintBitsToFloat(sun_grid_data[base + su + 1u]), f.z);
    float d = mix(uintBitsToFloat(sun_grid_data[base + sv]), uintBitsToFloat(sun_grid_data[base + sv + 1u]), f.z);
    float e = mix(uintBitsToFloat(sun_grid_data[base + sv + su]), uintBitsToFloat(sun_grid_data[base + sv + su + 1u]), f.z);
    return mix(mix(a, b, f.x), mix(d, e, f.x), f.y) + outsized;
}

// The distances t >= 0 along the ray o + t d whose point's ray toward the sun meets the box
// [bmin, bmax]: one interval (x < y), empty when x >= y. Closed form: on each axis the sun ray's
// parameter s inside the box's slab is an interval whose ends are linear in t, and a point is in
// the shadow where the slabs' intervals overlap at some s > 0, a set of linear inequalities in t.
// The shadow of a convex box along one direction is convex, so the set is one interval.
vec2 sun_box_shadow_span(vec3 o, vec3 d, vec3 bmin, vec3 bmax) {
    vec3 l = -frame.sun_dir.xyz;
    float t0 = 0.0, t1 = 3.0e38;
    // s_lo(t) = lo_a + lo_b t and s_hi(t) = hi_a + hi_b t per axis; an axis the sun ray runs along
    // bounds t itself and s not at all (free).
    vec3 lo_a, lo_b, hi_a, hi_b;
    bvec3 free_axis;
    for (int i = 0; i < 3; ++i) {
        free_axis[i] = abs(l[i]) < 1e-7;
        if (free_axis[i]) {
            // bmin <= o + t d <= bmax on this axis
            if (abs(d[i]) < 1e-20) {
                if (o[i] < bmin[i] || o[i] > bmax[i]) return vec2(1.0, 0.0);
            } else {
                float ta = (bmin[i] - o[i]) / d[i], tb = (bmax[i] - o[i]) / d[i];
                t0 = max(t0, min(ta, tb));
                t1 = min(t1, max(ta, tb));
            }
            lo_a[i] = lo_b[i] = hi_a[i] = hi_b[i] = 0.0;
            continue;
        }
        float inv = 1.0 / l[i];
        float a0 = (bmin[i] - o[i]) * inv, a1 = (bmax[i] - o[i]) * inv, b = -d[i] * inv;
        lo_a[i] = min(a0, a1);
        hi_a[i] = max(a0, a1);
        lo_b[i] = b;
        hi_b[i] = b;
    }
    // Every lower end (and s = 0) below every upper end: c + k t < 0 for c = lo_a - hi_a, k = lo_b - hi_b.
    for (int j = 0; j < 3; ++j) {
        if (free_axis[j]) continue;
        for (int i = -1; i < 3; ++i) {
            if (i >= 0 && free_axis[i]) continue;
            float c = (i < 0 ? 0.0 : lo_a[i]) - hi_a[j];
            float k = (i < 0 ? 0.0 : lo_b[i]) - hi_b[j];
            if (abs(k) < 1e-20) {
                if (c >= 0.0) return vec2(1.0, 0.0);
            } else if (k > 0.0) {
                t1 = min(t1, -c / k);
            } else {
                t0 = max(t0, -c / k);
            }
        }
    }
    return vec2(t0, t1);
}

// The accurate technique's box shadows along one view ray, found once per ray: the intervals of t in
// [0, t_opaque) in some box's shadow, merged and in order, as trace's (render/fast_tracer.cpp
// box_shadows, which take any number). Each box's interval is merged into the kept ones as it comes,
// so what must fit is the ray's disjoint shadows in front of its opaque surface, not the boxes: the
// ground's own shadow lies behind it, and a ray that misses it never enters it. With more disjoint
// shadows than fit, sun_box_span_count is SUN_BOX_SPANS_NONE and each sample tests the boxes itself
// (exact_integrator.glsl sun_node_transmittance). Before (2026-12-06), a scene of more than 8 boxes
// took that path on every ray: a ground and 8 poplars under a grazing sun read p99.9 1.4e-2 of the
// peak by ppll against trace's 3.8e-3 (the issue's bound: 1e-2).
const uint SUN_BOX_SPANS = 16u;
const uint SUN_BOX_SPANS_NONE = 0xffffffffu;
vec2 sun_box_spans[SUN_BOX_SPANS];
uint sun_box_span_count = SUN_BOX_SPANS_NONE;

void find_sun_box_spans(vec3 o, vec3 d, float t_opaque) {
    uint n = 0u;
    for (uint b = 0u; b < frame.counts.w; ++b) {
        vec2 s = sun_box_shadow_span(o, d, boxes[b].min_corner.xyz, boxes[b].max_corner.xyz);
        s.y = min(s.y, t_opaque);
        if (!(s.x < s.y)) continue;
        // The kept spans [i, j) that s overlaps or touches become one with it (touching ones merge, as
        // trace's do); the spans after j move to close the gap, or to make room where s is new.
        uint i = 0u;
        while (i < n && sun_box_spans[i].y < s.x) ++i;
        uint j = i;
        while (j < n && sun_box_spans[j].x <= s.y) ++j;
        if (j > i) {
            s = vec2(min(s.x, sun_box_spans[i].x), max(s.y, sun_box_spans[j - 1u].y));
            uint removed = j - i - 1u;
            for (uint k = j; k < n; ++k) sun_box_spans[k - removed] = sun_box_spans[k];
            n -= removed;
        } else {
            if (n == SUN_BOX_SPANS) {
                sun_box_span_count = SUN_BOX_SPANS_NONE;
                return;
            }
            for (uint k = n; k > i; --k) sun_box_spans[k] = sun_box_spans[k - 1u];
            ++n;
        }
        sun_box_spans[i] = s;
    }
    sun_box_span_count = n;
}

// The spheres' part of T_sun in the media by the accurate technique, exp(-map depth); x = eye + rel.
float sun_media_map_transmittance(vec3 rel) {
    if (sun_grid.map_size.x == 0u) return 1.0;  // no sphere casts a shadow
    return exp(-sun_map_depth(rel));
}

#endif
