#version 460
// sorted: one camera-facing planar billboard per sphere, in back-to-front order (sorted_particle.glsl).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "screen_bounds.glsl"
#include "sorted_particle.glsl"

void main() { emit_sorted_particle(true); }
