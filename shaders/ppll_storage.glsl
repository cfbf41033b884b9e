// The per-pixel linked lists: head pointers, counters and the node pool (split into parts).
#ifndef BRUME_PPLL_STORAGE_GLSL
#define BRUME_PPLL_STORAGE_GLSL

layout(set = 0, binding = BINDING_HEADS, std430) coherent buffer HeadBlock { uint heads[]; };
layout(set = 0, binding = BINDING_COUNTERS, std430) coherent buffer CounterBlock { ListCounters counters; };
layout(set = 0, binding = BINDING_POOL, std430) buffer PoolPart { uvec4 nodes[]; } pool[MAX_POOL_PARTS];

// How many pool parts exist, as a specialization constant: a CPU device runs every case of a switch
// under a lane mask, so the usual one-part pool must compile to a single plain access.
layout(constant_id = 1) const uint POOL_PARTS = 1;

#define BRUME_POOL_CASE(k) case k: pool[k].nodes[offset] = node; break;
void store_node(uint index, uvec4 node) {
    if (POOL_PARTS == 1u) {
        pool[0].nodes[index] = node;
        return;
    }
    uint offset = index & ((1u << frame.pool.y) - 1u);
    switch (index >> frame.pool.y) {
        BRUME_POOL_CASE(0) BRUME_POOL_CASE(1) BRUME_POOL_CASE(2) BRUME_POOL_CASE(3)
        BRUME_POOL_CASE(4) BRUME_POOL_CASE(5) BRUME_POOL_CASE(6) BRUME_POOL_CASE(7)
    }
}
#undef BRUME_POOL_CASE

#define BRUME_POOL_CASE(k) case k: return pool[k].nodes[offset];
uvec4 load_node(uint index) {
    if (POOL_PARTS == 1u) return pool[0].nodes[index];
    uint offset = index & ((1u << frame.pool.y) - 1u);
    switch (index >> frame.pool.y) {
        BRUME_POOL_CASE(0) BRUME_POOL_CASE(1) BRUME_POOL_CASE(2) BRUME_POOL_CASE(3)
        BRUME_POOL_CASE(4) BRUME_POOL_CASE(5) BRUME_POOL_CASE(6) BRUME_POOL_CASE(7)
    }
    return uvec4(0u, 0u, 0u, LIST_END);
}
#undef BRUME_POOL_CASE

#endif
