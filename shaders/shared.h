// Structs and bindings shared by C++ and GLSL, written once (GUIDE section 4).
// Every member is a vec4/uvec4 so std140, std430 and scalar layouts agree with C++; the C++ side
// static_asserts sizes and offsets (render/vk/shared_layout.cpp), so a change here that breaks the
// match fails to compile instead of silently shifting fields.
#ifndef BRUME_SHADERS_SHARED_H
#define BRUME_SHADERS_SHARED_H

#ifdef __cplusplus
#include <glm/vec4.hpp>
#include <cstdint>
namespace brume::gpu {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#define BRUME_CONST inline constexpr uint
#else
#define BRUME_CONST const uint
#endif

// Descriptor set 0, shared by every pass of every method.
BRUME_CONST BINDING_FRAME = 0;     // uniform FrameUniforms
BRUME_CONST BINDING_SPHERES = 1;   // buffer GpuSphere[]
BRUME_CONST BINDING_BOXES = 2;     // buffer GpuBox[]
BRUME_CONST BINDING_OPAQUE = 3;    // storage image rgba32f: rgb = opaque radiance, a = distance along the ray
BRUME_CONST BINDING_HEADS = 4;     // buffer uint[]: head node of each pixel's list, LIST_END if empty
BRUME_CONST BINDING_COUNTERS = 5;  // buffer ListCounters
BRUME_CONST BINDING_POOL = 6;      // buffer uvec4[] x MAX_POOL_PARTS: the node pool, in parts
// lavapipe's maxStorageBufferRange is 128 MiB, so the pool is split into parts of at most that size.
// Shaders pick a part with a switch over constant indices, which needs no descriptor-indexing
// feature (lavapipe 22.3 has none).
BRUME_CONST MAX_POOL_PARTS = 8;
// Bindings a method may use for its own data (e.g. a sort order, per-pixel k-buffers, peeling
// depths). Formats and meanings are each method's own; a binding no pipeline uses stays unwritten.
BRUME_CONST BINDING_AUX_BUFFER0 = 7;  // storage buffers 7..10
BRUME_CONST AUX_BUFFERS = 4;
BRUME_CONST BINDING_AUX_IMAGE0 = 11;  // storage images 11..14 (layout GENERAL)
BRUME_CONST AUX_IMAGES = 4;
BRUME_CONST BINDING_COUNT = BINDING_AUX_IMAGE0 + AUX_IMAGES;

BRUME_CONST LIST_END = 0xFFFFFFFFu;
// The resolve gathers list statistics (max length, non-empty pixels) only when asked: their atomics
// on one shared cache line cost as much as resolving a short list on a 2-core CPU device.
BRUME_CONST FRAME_COLLECT_LIST_STATS = 1u;
BRUME_CONST NODE_BYTES = 16;  // one uvec4 per node; asserted against the GLSL stride below

// One list node is one sphere's whole visible interval along the pixel ray:
//   x = floatBitsToUint(t_entry), y = floatBitsToUint(t_exit), z = sphere index, w = next node.
// Entry and exit live in one node, so overflow can never keep one without the other.

struct FrameUniforms {
    vec4 eye;         // xyz: eye position
    vec4 forward;     // xyz: unit view direction
    vec4 right;       // xyz: unit right * tan(fov/2) * aspect; w: tan(fov/2) * aspect
    vec4 up;          // xyz: unit up * tan(fov/2);            w: tan(fov/2)
    vec4 ambient;     // rgb: L_ambient
    vec4 sun;         // rgb: L_sun
    vec4 sun_dir;     // xyz: unit direction the sunlight travels
    vec4 background;  // rgb: radiance where a ray meets no opaque surface
    uvec4 counts;     // x: width, y: height, z: sphere count, w: box count
    uvec4 pool;       // x: node capacity, y: log2(nodes per pool part), z: pool parts, w: FRAME_* flags
    vec4 params;      // x: min transmittance, yzw: unused
};

struct GpuSphere {
    vec4 center_radius;      // xyz centre, w radius
    vec4 albedo_extinction;  // rgb albedo, w extinction tau
};

struct GpuBox {
    vec4 min_corner;  // xyz
    vec4 max_corner;  // xyz
    vec4 radiance;    // rgb
};

// Written by the particle pass (allocated) and the resolve pass (statistics); read back every frame.
struct ListCounters {
    uint allocated;        // nodes requested this frame; above capacity means the pool overflowed
    uint max_length;       // longest list, in nodes
    uint nonempty_pixels;  // pixels with at least one node
    uint long_lists;       // pixels whose list needed more than one resolve window
};

#ifdef __cplusplus
}  // namespace brume::gpu
#endif
#undef BRUME_CONST
#endif
