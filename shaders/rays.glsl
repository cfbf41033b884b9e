// Pixel rays and analytic intersections, the float twins of sim/camera_rays.h and render/reference.cpp.
#ifndef BRUME_RAYS_GLSL
#define BRUME_RAYS_GLSL

// Unnormalised ray direction at a point of the screen in Vulkan NDC (y down). It is affine in NDC,
// so vertex shaders emit it for noperspective interpolation.
vec3 ndc_ray(vec2 ndc) { return frame.forward.xyz + ndc.x * frame.right.xyz - ndc.y * frame.up.xyz; }

// Unit direction of the ray through framebuffer position p (pixel centres are at i + 0.5).
vec3 pixel_ray_direction(vec2 p) { return normalize(ndc_ray(2.0 * p / vec2(frame.counts.xy) - 1.0)); }

// Entry and exit distances of a unit ray through a sphere; returns false on a miss.
// The discriminant is r^2 - |oc - (oc.d) d|^2 rather than b^2 - c: no cancellation far from the sphere.
// `oc` is origin - centre, `r2` the squared radius.
bool intersect_sphere(vec3 oc, float r2, vec3 dir, out float t0, out float t1) {
    float b = dot(oc, dir);
    vec3 closest = oc - b * dir;
    float disc = r2 - dot(closest, closest);
    if (disc < 0.0) return false;
    // q-form: the root of larger magnitude without cancellation, the other from the product c / q.
    float q = -b - (b >= 0.0 ? sqrt(disc) : -sqrt(disc));
    float c = dot(oc, oc) - r2;
    float ta = q, tb = (q != 0.0) ? c / q : 0.0;  // q == 0 only for a ray tangent at its own origin
    t0 = min(ta, tb);
    t1 = max(ta, tb);
    return true;
}

// Slab test: distance to the first surface of a solid box along a ray (0 when the eye is inside).
bool intersect_box(vec3 origin, vec3 dir, vec3 lo, vec3 hi, out float t_hit) {
    vec3 inv = 1.0 / dir;
    vec3 ta = (lo - origin) * inv, tb = (hi - origin) * inv;
    // A ray parallel to a slab gives +-inf, or NaN when it lies on the slab's plane; max/min below
    // drop NaN in favour of the other operand, which keeps the test conservative on the boundary.
    vec3 tn = min(ta, tb), tf = max(ta, tb);
    float t_near = max(max(tn.x, tn.y), tn.z);
    float t_far = min(min(tf.x, tf.y), tf.z);
    if (t_far < max(t_near, 0.0) || t_near > t_far) return false;
    t_hit = max(t_near, 0.0);
    return true;
}

#endif
