#version 460
// ppll, pass 1: the exact entry and exit of the pixel ray through this fragment's sphere, clipped to
// the eye (media containing the eye start at 0) and to the opaque surface, appended to the pixel's
// list as one node. One atomicAdd per subgroup instead of per fragment: the global counter is the
// hot spot of list building (docs/performance.md, "Append").
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "bindings.glsl"
#include "rays.glsl"
#include "ppll_storage.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"

void main() {
    if (gl_HelperInvocation) return;  // no derivatives are used; helpers must not take part in the ballot
    ivec2 px = ivec2(gl_FragCoord.xy);
    float t0, t1;
    if (!intersect_sphere(v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), t0, t1)) return;
    t0 = t0 > 0.0 ? t0 : 0.0;  // written so, never max(): -0.0 would sort after every distance as bits
    t1 = min(t1, imageLoad(opaque_image, px).a);
    if (!(t1 > t0)) return;

    uvec4 ballot = subgroupBallot(true);
    uint base = 0u;
    if (subgroupElect()) base = atomicAdd(counters.allocated, subgroupBallotBitCount(ballot));
    uint index = subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
    // Past capacity nothing is written; the host sees allocated > capacity, grows the pool and
    // renders the frame again, so no list is ever resolved with a node missing.
    if (index >= frame.pool.x) return;
    uint next = atomicExchange(heads[uint(px.y) * frame.counts.x + uint(px.x)], index);
    store_node(index, uvec4(floatBitsToUint(t0), floatBitsToUint(t1), v_sphere, next));
}
