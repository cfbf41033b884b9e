// The C++ side of shaders/shared.h, with the layout checks that keep it in step with GLSL.
#pragma once

#include "shaders/shared.h"
#include "sim/scene.h"

#include <cstddef>

namespace brume::gpu {

static_assert(sizeof(FrameUniforms) == 11 * 16, "FrameUniforms must match its std140 GLSL layout");
static_assert(offsetof(FrameUniforms, eye) == 0);
static_assert(offsetof(FrameUniforms, background) == 7 * 16);
static_assert(offsetof(FrameUniforms, counts) == 8 * 16);
static_assert(offsetof(FrameUniforms, pool) == 9 * 16);
static_assert(offsetof(FrameUniforms, params) == 10 * 16);
static_assert(sizeof(GpuSphere) == 48 && offsetof(GpuSphere, albedo_extinction) == 16 &&
              offsetof(GpuSphere, emission_sun) == 32);
static_assert(sizeof(GpuBox) == 64 && offsetof(GpuBox, max_corner) == 16 && offsetof(GpuBox, radiance) == 32 &&
              offsetof(GpuBox, diffuse) == 48);
static_assert(sizeof(ListCounters) == 32 && offsetof(ListCounters, unresolved) == 16 && offsetof(ListCounters, allocated) == 0 &&
              offsetof(ListCounters, max_length) == 4 && offsetof(ListCounters, nonempty_pixels) == 8 &&
              offsetof(ListCounters, long_lists) == 12);
static_assert(SUN_MAX_WHOLE % 4 == 0 && SUN_MAX_WHOLE >= SUN_MAX_OUTSIZED, "outsized_depth packs four a vec4");
static_assert(sizeof(SunGridHeader) == 96 + SUN_MAX_WHOLE * 20 + 64 &&
                  offsetof(SunGridHeader, columns) == 96 + SUN_MAX_WHOLE * 20 + 32 &&
                  offsetof(SunGridHeader, column_size) == 96 + SUN_MAX_WHOLE * 20 + 48 &&
                  offsetof(SunGridHeader, grid_outsized) == 96 + SUN_MAX_WHOLE * 20 && offsetof(SunGridHeader, cell) == 32 &&
                  offsetof(SunGridHeader, size) == 48 && offsetof(SunGridHeader, map_origin) == 64 &&
                  offsetof(SunGridHeader, map_size) == 80 && offsetof(SunGridHeader, outsized) == 96 &&
                  offsetof(SunGridHeader, outsized_depth) == 96 + SUN_MAX_WHOLE * 16,
              "SunGridHeader must match its std430 GLSL layout");
static_assert(NODE_BYTES == sizeof(uvec4), "a node is one uvec4 (std430 stride 16)");
static_assert(sizeof(PeelControl) == 2 * PEEL_SLOTS * 16 + PEEL_SLOTS * 4 &&
                  offsetof(PeelControl, composite_args) == PEEL_SLOTS * 16 &&
                  offsetof(PeelControl, going_on) == 2 * PEEL_SLOTS * 16,
              "PeelControl must match its std430 GLSL layout");
static_assert(sizeof(PeelControl) <= 65536, "PeelControl is written with vkCmdUpdateBuffer (64 KiB at most)");
static_assert(sizeof(WeightParams) == 16 && offsetof(WeightParams, depth) == 0);
static_assert(sizeof(ToneMapParams) == 32 && offsetof(ToneMapParams, source) == 16, "push constants: 128 bytes at most");
static_assert(BINDING_SORT_ORDER < BINDING_METHOD_BUFFER_FIRST + METHOD_BUFFERS &&
                  BINDING_KBUF_EXITS < BINDING_METHOD_BUFFER_FIRST + METHOD_BUFFERS &&
                  BINDING_PEEL_CONTROL < BINDING_METHOD_BUFFER_FIRST + METHOD_BUFFERS &&
                  BINDING_PEEL_IDS < BINDING_COUNT && BINDING_STOCHASTIC_OPTICAL_DEPTH < BINDING_COUNT,
              "a method binding outside the method slots of the layout");

// Every position the device reads is relative to the eye, taken in double here: the frame's eye is
// the origin, and spheres, boxes and the sun grid are moved by -eye. In float, a scene 100,000 units
// from the world's origin kept 0.008 of a unit of its spheres' and boxes' positions, and ppll's edges
// were off by up to 0.13 of the peak (trace, which works relative to the eye, within 5e-3); relative
// to the eye, what float loses grows with the distance from the eye, as the picture's own scale does.

// Camera, lighting and counts of a scene (the eye at the origin); the method fills in `pool`.
FrameUniforms make_frame_uniforms(const Scene& scene);
// The sphere relative to `eye` (the scene's camera position). sun_transmittance: T_sun at the sphere's
// centre (render/sun_light.h), 1 without shadows.
GpuSphere to_gpu(const Sphere& sphere, const glm::dvec3& eye, double sun_transmittance);
GpuBox to_gpu(const Box& box, const glm::dvec3& eye);

}  // namespace brume::gpu
