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
static_assert(sizeof(GpuSphere) == 32 && offsetof(GpuSphere, albedo_extinction) == 16);
static_assert(sizeof(GpuBox) == 48 && offsetof(GpuBox, max_corner) == 16 && offsetof(GpuBox, radiance) == 32);
static_assert(sizeof(ListCounters) == 16 && offsetof(ListCounters, allocated) == 0 &&
              offsetof(ListCounters, max_length) == 4 && offsetof(ListCounters, nonempty_pixels) == 8 &&
              offsetof(ListCounters, long_lists) == 12);
static_assert(NODE_BYTES == sizeof(uvec4), "a node is one uvec4 (std430 stride 16)");

// Camera, lighting and counts of a scene; the method fills in `pool`.
FrameUniforms make_frame_uniforms(const Scene& scene);
GpuSphere to_gpu(const Sphere& sphere);
GpuBox to_gpu(const Box& box);

}  // namespace brume::gpu
