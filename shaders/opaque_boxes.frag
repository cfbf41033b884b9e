#version 460
// Opaque pass: the exact ray/box hit at the pixel centre (no rasteriser edge snapping), written as
// radiance + distance, with a depth that grows toward the eye so the nearest box wins. A lit box adds
// diffuse * (L_ambient + L_sun max(0, n.l) T_sun(hit)), n the normal of the face hit; from inside the
// box no face is crossed and only the ambient term is reflected (render/reference.cpp does the same).
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "rays.glsl"
#include "sun_transmittance.glsl"

layout(location = 0) flat in uint v_box;
layout(location = 0) out vec4 out_radiance_distance;

void main() {
    GpuBox box = boxes[v_box];
    vec3 dir = pixel_ray_direction(gl_FragCoord.xy);
    float t;
    if (!intersect_box(frame.eye.xyz, dir, box.min_corner.xyz, box.max_corner.xyz, t)) discard;
    vec3 radiance = box.radiance.rgb;
    if (any(greaterThan(box.diffuse.rgb, vec3(0.0)))) {
        vec3 irradiance = frame.ambient.rgb;
        if (t > 0.0) {
            // The face entered is on the axis whose slab the ray enters last.
            vec3 inv = 1.0 / dir;
            vec3 tn = min((box.min_corner.xyz - frame.eye.xyz) * inv, (box.max_corner.xyz - frame.eye.xyz) * inv);
            int axis = tn.x >= tn.y && tn.x >= tn.z ? 0 : (tn.y >= tn.z ? 1 : 2);
            float toward_sun = -frame.sun_dir[axis];
            float n_dot_l = dir[axis] > 0.0 ? -toward_sun : toward_sun;
            if (n_dot_l > 0.0)
                irradiance += frame.sun.rgb * (n_dot_l * sun_transmittance(frame.eye.xyz + t * dir, v_box));
        }
        radiance += box.diffuse.rgb * irradiance;
    }
    out_radiance_distance = vec4(radiance, t);
    // 1/(1+t) keeps float's relative precision at every distance (depth compare GREATER, cleared to 0).
    gl_FragDepth = 1.0 / (1.0 + t);
}
