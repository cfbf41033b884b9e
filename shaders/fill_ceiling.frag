#version 460
// `brume bench layers`' fill ceiling: the sphere impostors of every method, with the cheapest
// fragment shader a driver must still run. The discard tests a flat varying no sphere has, so it is
// never taken, but the compiler cannot prove it, and the write keeps the fragment alive: what is
// left is rasterisation, the varyings and one colour write per fragment.
#extension GL_GOOGLE_include_directive : require
#include "impostor_interface.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    if (v_sphere == 0xffffffffu) discard;
    out_radiance = vec4(v_ray, 1.0);
}
