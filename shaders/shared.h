// Structs and bindings shared by C++ and GLSL, written once. Members are vec4/uvec4 (or arrays of
// uint in std430 blocks) so std140, std430 and C++ agree; the C++ side static_asserts sizes and
// offsets (render/vk/gpu_types.h), so a change here that breaks the match fails to compile instead
// of silently shifting fields.
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
#define BRUME_CONST_FLOAT inline constexpr float
#define BRUME_CONST_INT inline constexpr int
#else
#define BRUME_CONST const uint
#define BRUME_CONST_FLOAT const float
#define BRUME_CONST_INT const int
#endif

// Descriptor set 0, the one layout every pass of every method uses (render/vk/descriptors.cpp).
// Bindings 0..3 are the frame's, written by the frame path into every method's set.
BRUME_CONST BINDING_FRAME = 0;     // uniform FrameUniforms
BRUME_CONST BINDING_SPHERES = 1;   // buffer GpuSphere[]
BRUME_CONST BINDING_BOXES = 2;     // buffer GpuBox[]
BRUME_CONST BINDING_OPAQUE = 3;    // storage image rgba32f: rgb = opaque radiance, a = distance along the ray
// ppll's lists.
BRUME_CONST BINDING_HEADS = 4;     // buffer uint[]: head node of each pixel's list, LIST_END if empty
BRUME_CONST BINDING_COUNTERS = 5;  // buffer ListCounters
BRUME_CONST BINDING_POOL = 6;      // buffer uvec4[] x MAX_POOL_PARTS: the node pool, in parts
// lavapipe's maxStorageBufferRange is 128 MiB, so the pool is split into parts of at most that size.
// Shaders pick a part with a switch over constant indices, which needs no descriptor-indexing
// feature (lavapipe 22.3 has none).
BRUME_CONST MAX_POOL_PARTS = 8;

// Bindings 7..14 belong to one method at a time: four storage buffers (7..10) and four storage
// images in GENERAL layout (11..14). Each method names the ones it uses below; a binding no
// pipeline of the method uses stays unwritten.
BRUME_CONST BINDING_METHOD_BUFFER_FIRST = 7;
BRUME_CONST METHOD_BUFFERS = 4;
BRUME_CONST BINDING_METHOD_IMAGE_FIRST = 11;
BRUME_CONST METHOD_IMAGES = 4;
// The light's, written by the frame path into every method's set like bindings 0..3.
BRUME_CONST BINDING_SUN_GRID = BINDING_METHOD_IMAGE_FIRST + METHOD_IMAGES;  // buffer SunGridHeader, uint[]
BRUME_CONST BINDING_COUNT = BINDING_SUN_GRID + 1;

// sorted, soft, auto's power-sorted frames, ppll
BRUME_CONST BINDING_SORT_ORDER = 7;      // buffer uint[]: draw i shows sphere order[i]
// ppll
BRUME_CONST BINDING_PPLL_BOUNDS = 8;     // buffer float[]: per sphere, a lower bound of its ray events' distances
// tiles (render/methods/tiles.h); frame.pool: x tiles per row, y rows, z the probe's loop count (2), w FRAME_* flags
BRUME_CONST TILE_SIZE = 8;               // pixels per tile side: one compute workgroup per tile
BRUME_CONST BINDING_TILE_FIRST = 7;      // buffer uint[tiles + 1]: tile t's spheres are entries[first[t] .. first[t+1])
BRUME_CONST BINDING_TILE_ENTRIES = 8;    // buffer uvec2[]: (sphere, floatBitsToUint(its nearest bound)), near to far
BRUME_CONST BINDING_RADIANCE_BUFFER = 9;  // buffer vec4[width * height]: the resolved radiance, row by row
                                          // (tiles, and auto's reference frames: shaders/radiance_buffer.frag)
// wsum, wavg, wboit
BRUME_CONST BINDING_WEIGHT_PARAMS = 7;   // buffer WeightParams
BRUME_CONST BINDING_WEIGHT_ACCUM = 11;   // rgba32f: sum(w alpha c), sum(w alpha)
BRUME_CONST BINDING_WEIGHT_EXTRA = 12;   // r32f: the mode's second sum (optical depth sum(tau * chord), or wavg's count)
// kbuf
BRUME_CONST BINDING_KBUF_KEYS = 7;       // buffer uint[pixel * k + slot]: entry keys, 0xffffffff empty
BRUME_CONST BINDING_KBUF_IDS = 8;        // buffer uint[]: sphere per slot
BRUME_CONST BINDING_KBUF_EXITS = 9;      // buffer float[]: clipped exit distance per slot
BRUME_CONST BINDING_KBUF_TAIL_ACCUM = 11;          // rgba32f: sum(alpha c), sum(alpha) of the tail
BRUME_CONST BINDING_KBUF_TAIL_OPTICAL_DEPTH = 12;  // r32f: sum(tau * chord) of the tail
// peel (classic and dual)
BRUME_CONST BINDING_PEEL_ACCUM = 7;      // buffer vec4[]: the composited result so far, per pixel
BRUME_CONST BINDING_PEEL_CONTROL = 8;    // buffer PeelControl
BRUME_CONST BINDING_PEEL_KEYS0 = 11;     // classic: rgba32ui keys, ping-pong pair
BRUME_CONST BINDING_PEEL_KEYS1 = 12;
BRUME_CONST BINDING_PEEL_STATE = 11;     // dual: rgba32f (-near, far, fcur, bcur)
BRUME_CONST BINDING_PEEL_WINDOW = 12;    // dual: rgba32f
BRUME_CONST BINDING_PEEL_TAIL = 13;      // rgba32f: sum (x c, x) of every sphere
BRUME_CONST BINDING_PEEL_IDS = 14;       // dual: rgba32f
// stochastic
BRUME_CONST BINDING_STOCHASTIC_LAYERS = 11;         // rgba32f array (r32f for ',depth'): one layer per pass
BRUME_CONST BINDING_STOCHASTIC_ACCUM = 12;          // rgba32f: sum(alpha c), sum(alpha)
BRUME_CONST BINDING_STOCHASTIC_OPTICAL_DEPTH = 13;  // r32f
// screendoor
BRUME_CONST BINDING_SCREENDOOR_SUBSAMPLES = 11;     // rgba32f, S x S subsamples per pixel

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
    vec4 params;      // x: min transmittance; y: peel's depth scale 2^-k (peel only); z: 1 with shadows, else 0;
                      // w: 1 with shadows by the accurate technique (exact_integrator.glsl), else 0
};

struct GpuSphere {
    vec4 center_radius;      // xyz centre, w radius
    vec4 albedo_extinction;  // rgb albedo, w extinction tau
    // rgb: emission (the radiance the medium alone shows when optically thick); w: T_sun at the centre
    // (render/sun_light.h, the per-sphere shadow technique), 1 without shadows.
    vec4 emission_sun;
};

struct GpuBox {
    vec4 min_corner;  // xyz
    vec4 max_corner;  // xyz
    vec4 radiance;    // rgb
    vec4 diffuse;     // rgb: reflectance of the sun and ambient light
};

// The light-space grid of render/sun_light.h: the plane perpendicular to the sun split into size.x^2
// square cells, each listing the spheres whose shadow disc overlaps it, so that T_sun at a point tests
// only the spheres whose shadow cylinder can hold it. In its buffer the header is followed by
// size.x^2 + 1 cell offsets into the sphere list, then the list.
// With the accurate shadow technique the buffer also holds the spheres' optical depth toward the sun
// on a light-space lattice (render/sun_depth_map.h), as float bits from word map_size.w of the data:
// vertex (i, j, k) at (j * map_size.x + i) * map_size.z + k. A point eye + r has lattice coordinates
// map_origin.xyz + (dot(r, u), dot(r, v), dot(r, l)) * map_origin.w, l = -sun direction.
// The most spheres the map takes whole (render/sun_depth_map.h kMaxWholeSpheres): every sphere of a
// scene of at most this many, else the grid's outsized ones (at most SUN_MAX_OUTSIZED).
BRUME_CONST SUN_MAX_WHOLE = 48;
struct SunGridHeader {
    vec4 u_axis;      // xyz: unit u of the plane; w: u of the grid's first cell edge
    vec4 v_axis;      // xyz: unit v; w: v of the grid's first cell edge
    vec4 cell;        // x: cell side; yzw: unused
    uvec4 size;       // x: cells per side (0: no grid, no sphere casts a shadow); y: entries in the sphere list;
                      // z: the map's whole spheres (at most SUN_MAX_WHOLE): the grid's outsized ones, or
                      // every sphere of a scene of at most SUN_MAX_WHOLE (render/sun_depth_map.h);
                      // w: the grid's outsized
    vec4 map_origin;  // xyz: the eye's lattice coordinates; w: 1 / lattice spacing
    uvec4 map_size;   // xyz: vertices along u, v, s (x = 0: no map); w: the map's first word in the data
    // The spheres the map leaves to a closed form (render/sun_depth_map.h Outsized), in lattice units:
    // xyz the centre, w radius^2; and each one's tau * spacing, in order (SUN_MAX_WHOLE at most).
    vec4 outsized[SUN_MAX_WHOLE];
    vec4 outsized_depth[SUN_MAX_WHOLE / 4];  // sphere k's in [k / 4][k % 4]
    // The same spheres as the grid leaves them out of every cell (render/sun_light.h outsized_indices):
    // their indices into the sphere buffer, size.w of them, k's in [k / 4][k % 4]; a lookup adds their
    // chords.
    uvec4 grid_outsized[2];
    // A sparse cloud's spheres taken exactly through light-space columns (render/sun_depth_map.h
    // Columns; the lattice then the least one, of zeros): xy the first column's corner in lattice
    // coordinates, z 1 / column side (lattice units); w unused.
    vec4 columns;
    // x, y: columns along u and v (x = 0: none); z: the word of the data where the nu * nv + 1 offsets
    // begin; w: the word where the spheres begin, SUN_COLUMN_WORDS each (u, v, s, radius^2,
    // tau * spacing, top: float bits), after the offsets.
    uvec4 column_size;
};
BRUME_CONST SUN_COLUMN_WORDS = 6;
BRUME_CONST SUN_MAX_OUTSIZED = 8;

// The accurate technique's pieces along a view segment, the same on the CPU (render/sun_jobs.h, where
// each one's choice is measured) and the GPU (shaders/exact_integrator.glsl sun_segment_integral): the
// depth toward the sun is read at the ends of pieces of at most SUN_PIECE_CELLS map cells (in thin
// media up to SUN_PIECE_THIN_WIDEN times that, while sigma_t len stays within SUN_PIECE_THIN_DEPTH),
// taken as linear between them, and a piece is halved, up to SUN_PIECE_SPLITS times, where the light
// it may carry times its change of depth exceeds SUN_PIECE_DEPTH_CHANGE; a segment takes at most
// SUN_MAX_PIECES pieces before halving. Written once, so trace and the GPU methods cut the same pieces.
BRUME_CONST_FLOAT SUN_PIECE_CELLS = 4.0f;
BRUME_CONST_INT SUN_PIECE_SPLITS = 4;
BRUME_CONST_FLOAT SUN_PIECE_DEPTH_CHANGE = 0.1f;
BRUME_CONST_FLOAT SUN_PIECE_THIN_DEPTH = 0.25f;
BRUME_CONST_FLOAT SUN_PIECE_THIN_WIDEN = 4.0f;
BRUME_CONST_FLOAT SUN_MAX_PIECES = 256.0f;

// Written by the particle pass (allocated) and the resolve pass (statistics); read back every frame.
struct ListCounters {
    uint allocated;        // nodes requested this frame; above capacity means the pool overflowed
    uint max_length;       // longest list, in nodes
    uint nonempty_pixels;  // pixels with at least one node
    uint long_lists;       // pixels the ordered path could not resolve: resolved by the general path
    uint unresolved;       // pixels whose resolve the device cut short (a loop limit): the frame is wrong
    uint reserved0, reserved1, reserved2;
};

// The tone-map pass (render/frame/tone_map.h) has a set layout of its own: the HDR target, sampled.
BRUME_CONST BINDING_TONE_MAP_HDR = 0;  // combined image sampler, rgba32f, SHADER_READ_ONLY_OPTIMAL
// Its push constants.
struct ToneMapParams {
    vec4 scale;      // x: exposure scale 2^stops; yzw: unused
    vec4 source;     // xy: HDR texels per target pixel (1 when the sizes match); zw: HDR extent
};

// peel's control block (shaders/peel_*composite.frag): indirect draws of every geometry pass and
// composite, which the composites switch on, and per-pass counts read back by the CPU.
BRUME_CONST PEEL_MAX_PASSES = 64;
BRUME_CONST PEEL_SLOTS = PEEL_MAX_PASSES + 2;  // geometry passes (dual: + its window pass) and the tail
struct PeelControl {
    uvec4 peel_args[PEEL_SLOTS];       // VkDrawIndirectCommand: 6 vertices, spheres or 0, firstVertex 6 p, 0
    uvec4 composite_args[PEEL_SLOTS];  // 3 vertices, 1 or 0 instances, firstVertex 3 p, 0
    uint going_on[PEEL_SLOTS];         // pixels that may have more to peel after pass p (std430: stride 4)
};

// The weighted methods' parameters (shaders/weighted_accumulate.frag).
struct WeightParams {
    vec4 depth;  // x: the depth scale D of McGuire & Bavoil's weight; yzw: unused
};

#ifdef __cplusplus
}  // namespace brume::gpu
#endif
#undef BRUME_CONST
#endif
