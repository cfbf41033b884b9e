#version 460
// The preview's heat map of list length (render/frame/list_heat_map.h): one count per sphere whose
// clipped interval the pixel ray meets, added into the HDR target's red channel. The test is
// ppll_append.frag's, written the same way over the same impostors, so each pixel's count is the
// length its ppll list has, without touching ppll's own passes.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
#include "impostor_interface.glsl"

layout(location = 0) out vec4 out_count;

void main() {
    float t0, t1;
    if (!intersect_sphere(v_offset_r2.xyz, v_offset_r2.w, normalize(v_ray), t0, t1)) discard;
    t0 = t0 > 0.0 ? t0 : 0.0;
    t1 = min(t1, imageLoad(opaque_image, ivec2(gl_FragCoord.xy)).a);
    if (!(t1 > t0)) discard;
    out_count = vec4(1.0, 0.0, 0.0, 0.0);
}
