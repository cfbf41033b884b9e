#version 460
// One impostor rectangle per sphere, read straight from the sphere buffer (no CPU-built mesh):
// instance i draws sphere i as 6 vertices. Spheres without extinction change no pixel and are culled.
// Per-sphere constants travel as flat varyings and the pixel ray as a noperspective one (it is
// linear in screen space), so the fragment shader reads no buffer and divides nothing to set up
// its intersection: on a CPU device those gathers and divisions were most of the append cost.
//
// Methods that draw the spheres several times a frame (peel's passes, stochastic's coverage passes)
// pass the pass number in firstVertex: pass p draws vertices 6p .. 6p + 5, and v_pass = p (the
// pipeline layout has no push constants). Every pass runs this same compiled code, so an entry
// distance found in one pass compares bit for bit with the same sphere's in the next.
#extension GL_GOOGLE_include_directive : require
#define BRUME_INSTANCE_SPHERE uint(gl_InstanceIndex)
#include "sphere_impostor.glsl"
