// Descriptor declarations shared by every Brume shader (set 0, see shared.h).
#ifndef BRUME_BINDINGS_GLSL
#define BRUME_BINDINGS_GLSL
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(set = 0, binding = BINDING_FRAME, std140) uniform FrameBlock { FrameUniforms frame; };
layout(set = 0, binding = BINDING_SPHERES, std430) readonly buffer SphereBlock { GpuSphere spheres[]; };
layout(set = 0, binding = BINDING_BOXES, std430) readonly buffer BoxBlock { GpuBox boxes[]; };
layout(set = 0, binding = BINDING_SUN_GRID, std430) readonly buffer SunGridBlock {
    SunGridHeader sun_grid;
    uint sun_grid_data[];  // size.x^2 + 1 cell offsets, then the sphere list
};

#endif
