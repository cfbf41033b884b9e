#version 460
// soft: one spherical billboard per sphere, in back-to-front order (sorted_particle.glsl).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "screen_bounds.glsl"
#include "sorted_particle.glsl"

void main() { emit_sorted_particle(false); }
