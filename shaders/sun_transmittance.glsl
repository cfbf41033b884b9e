// T_sun at a point (docs/accuracy.md, "Light through the smoke"), the float twin of render/sun_light.h:
// 0 if the ray x + s l (s > 0, l toward the sun) meets a box, else exp(-sum_k tau_k len_k(x)). The
// spheres come from the light-space grid (SunGridHeader in shared.h): only those whose shadow disc
// overlaps x's cell. The opaque pass evaluates it once per lit box fragment. In the media, the per-sphere
// technique uses the values in GpuSphere.emission_sun.w, and the accurate one sun_media_transmittance
// below (the light-space depth map).
// Needs bindings.glsl and rays.glsl.
#ifndef BRUME_SUN_TRANSMITTANCE_GLSL
#define BRUME_SUN_TRANSMITTANCE_GLSL

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
    if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(int(side))))) return 1.0;
    uint c = uint(cell.y) * side + uint(cell.x);
    uint first = sun_grid_data[c], last = sun_grid_data[c + 1u];
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
    return exp(-depth);
}

// The spheres' optical depth toward the sun at eye + rel, from the accurate technique's light-space
// map (render/sun_depth_map.h; SunGridHeader.map_*): trilinear between vertices that hold it exactly.
// Loop-free: its cost does not grow with the smoke above the point.
float sun_map_depth(vec3 rel) {
    uvec3 n = sun_grid.map_size.xyz;
    vec3 g = sun_grid.map_origin.xyz +
             vec3(dot(rel, sun_grid.u_axis.xyz), dot(rel, sun_grid.v_axis.xyz), dot(rel, -frame.sun_dir.xyz)) *
                 sun_grid.map_origin.w;
    // Outside the lattice's columns (or NaN): outside every shadow cylinder.
    if (!(g.x >= 0.0 && g.y >= 0.0 && g.x < float(n.x - 1u) && g.y < float(n.y - 1u))) return 0.0;
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
    return mix(mix(a, b, f.x), mix(d, e, f.x), f.y);
}

// T_sun in the media by the accurate technique: 0 in a box's shadow (exact), else exp(-map depth).
// x = eye + rel.
float sun_media_transmittance(vec3 x, vec3 rel) {
    if (frame.params.z == 0.0) return 1.0;
    if (sun_box_blocked(x, 0xffffffffu)) return 0.0;
    if (sun_grid.map_size.x == 0u) return 1.0;  // no sphere casts a shadow
    return exp(-sun_map_depth(rel));
}

#endif
