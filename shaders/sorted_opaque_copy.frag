#version 460
// sorted, soft: fill the HDR target with the opaque image's radiance, the background the billboards
// are blended over (a plain copy: the opaque image is a storage image, not an attachment).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(set = 0, binding = BINDING_OPAQUE, rgba32f) uniform readonly image2D opaque_image;
layout(location = 0) noperspective in vec3 v_ray;  // fullscreen_ray.vert's output, unused here
layout(location = 0) out vec4 out_radiance;

void main() { out_radiance = vec4(imageLoad(opaque_image, ivec2(gl_FragCoord.xy)).rgb, 1.0); }
