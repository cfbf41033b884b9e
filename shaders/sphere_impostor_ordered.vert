#version 460
// The sphere impostors of sphere_impostor.vert, drawn in a host-chosen order: instance i draws sphere
// draw_order[i]. ppll draws its spheres far to near (by their nearest possible distance), so each
// pixel's list, which the head exchange builds in reverse append order, arrives nearly sorted.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
layout(set = 0, binding = BINDING_SORT_ORDER, std430) readonly buffer OrderBlock { uint draw_order[]; };
#define BRUME_INSTANCE_SPHERE draw_order[gl_InstanceIndex]
#include "sphere_impostor.glsl"
