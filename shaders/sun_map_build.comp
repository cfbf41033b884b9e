#version 450
// The accurate shadow technique's light-space depth map (render/sun_depth_map.h), built on the device
// in the frame path's light pass (render/frame/sun_map_pass.h, from FramePath::record_shared_passes)
// where the CPU only planned its lattice (SunDepthMap::plan): each invocation fills one column (i, j)
// of the lattice, the vertices along s from the bottom (k = 0, below every sphere) to the top
// (k = ns - 1, at or above every sphere), as the CPU's build does:
//   depth(k) = sum over cells c >= k of inc(c),  inc(c) = sum over spheres of tau |[c, c + 1] ∩ chord|,
// in lattice units (one unit a spacing, tau times the spacing per unit of chord). The spheres are those
// that the sun grid's cell of the column lists (every sphere whose shadow disc covers the column; the
// outsized ones are in no cell, and a lookup adds them in closed form, as on the CPU). The column
// holds its cells' increments first, then their suffix sums, in place: the map's own words are its
// scratch. Float sums where the CPU's are double: the same map to float rounding.
// A workgroup a column instead (each invocation a run of the column's cells, the runs' sums joined in
// shared memory) computed every sphere's chord in all 64 invocations and waited at two barriers a
// column: on lavapipe campfire's map took 7.4 s against this one's 109 ms (lavapipe takes the
// host's build, 2.9 ms there). Neither has been timed on a GPU yet; this is the simpler.
#extension GL_GOOGLE_include_directive : require

#include "shared.h"

layout(local_size_x = 64) in;

layout(set = 0, binding = BINDING_FRAME, std140) uniform FrameBlock { FrameUniforms frame; };
layout(set = 0, binding = BINDING_SPHERES, std430) readonly buffer SphereBlock { GpuSphere spheres[]; };
// The sun buffer as shaders/bindings.glsl declares it, but written: the map's words follow the grid's.
layout(set = 0, binding = BINDING_SUN_GRID, std430) buffer SunGridBlock {
    SunGridHeader sun_grid;
    uint sun_grid_data[];
};

void main() {
    uvec3 n = sun_grid.map_size.xyz;
    uint columns = n.x * n.y;
    uint side = sun_grid.size.x;
    uint items = side * side + 1u;  // the grid's sphere list follows its offsets
    float inverse_cell = sun_grid.map_origin.w;
    float spacing = 1.0 / inverse_cell;
    vec3 l = -frame.sun_dir.xyz;
    float top_vertex = float(n.z - 1u);
    // A grid-stride loop: the columns may outnumber what one dispatch's groups cover.
    for (uint column = gl_GlobalInvocationID.x; column < columns; column += gl_NumWorkGroups.x * 64u) {
        uint i = column % n.x, j = column / n.x;
        uint base = sun_grid.map_size.w + column * n.z;
        for (uint k = 0u; k < n.z; ++k) sun_grid_data[base + k] = floatBitsToUint(0.0);
        // The column's position across the sun's rays, relative to the eye, and its cell of the grid.
        vec2 uv = (vec2(float(i), float(j)) - sun_grid.map_origin.xy) * spacing;
        ivec2 cell = ivec2(floor((uv - vec2(sun_grid.u_axis.w, sun_grid.v_axis.w)) / sun_grid.cell.x));
        bool inside = all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, ivec2(int(side))));
        uint c = inside ? uint(cell.y) * side + uint(cell.x) : 0u;
        uint first = sun_grid_data[c], last = inside ? sun_grid_data[c + 1u] : first;
        for (uint m = first; m < last; ++m) {
            GpuSphere g = spheres[sun_grid_data[items + m]];
            float tau = g.albedo_extinction.w;
            if (!(tau > 0.0)) continue;
            // The sphere in lattice coordinates, as a lookup takes a point (sun_map_depth).
            vec3 centre = sun_grid.map_origin.xyz +
                          vec3(dot(g.center_radius.xyz, sun_grid.u_axis.xyz), dot(g.center_radius.xyz, sun_grid.v_axis.xyz),
                               dot(g.center_radius.xyz, l)) * inverse_cell;
            float r = g.center_radius.w * inverse_cell;
            float du = float(i) - centre.x, dv = float(j) - centre.y;
            float h2 = r * r - (du * du + dv * dv);
            if (!(h2 > 0.0)) continue;
            float half_chord = sqrt(h2);
            float bottom = clamp(centre.z - half_chord, 0.0, top_vertex), top = clamp(centre.z + half_chord, 0.0, top_vertex);
            float per_unit = tau * spacing;  // optical depth per lattice unit of chord
            // Cell k is [k, k + 1]: its share of the chord.
            for (uint k = uint(bottom); k < min(uint(ceil(top)), n.z - 1u); ++k) {
                float part = min(top, float(k + 1u)) - max(bottom, float(k));
                uint at = base + k;
                sun_grid_data[at] = floatBitsToUint(uintBitsToFloat(sun_grid_data[at]) + per_unit * max(part, 0.0));
            }
        }
        // depth(k): the increments of the cells from k up, summed from the top (where it is 0).
        float running = 0.0;
        for (uint k = n.z; k > 0u;) {
            --k;
            running += uintBitsToFloat(sun_grid_data[base + k]);
            sun_grid_data[base + k] = floatBitsToUint(running);
        }
    }
}
