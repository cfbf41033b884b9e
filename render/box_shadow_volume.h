// A box's shadow volume, the points x with x + s l in the box for some s >= 0 (l toward the sun), as the
// intersection of its bounding planes, set up once per frame so that each view ray from one origin
// takes its interval in the shadow by a few float products: trace's accurate shadow technique
// (render/fast_tracer.cpp) asks it once per ray and box. The closed form it must agree with, in double,
// is render/sun_light.h box_shadow_interval (tests/test_box_shadow_volume.cpp holds them together).
//
// The volume is the box swept away from the sun, a convex polyhedron whose faces are the box's faces
// that the sun reaches or grazes (n . l >= 0) and the planes through the box's silhouette edges that
// hold l. Coordinates are relative to the origin (the eye), so float keeps its precision there.
#pragma once

#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace brume {

class BoxShadowVolume {
public:
    BoxShadowVolume(const Box& box, const glm::dvec3& toward_sun, const glm::dvec3& origin);

    // The interval [t_lo, t_hi] of t along origin + t d inside the volume (t_lo may be -inf, t_hi +inf);
    // false when the line misses it.
    bool interval(float dx, float dy, float dz, float& t_lo, float& t_hi) const;

    // interval() for eight rays at once, one a lane (arrays of 8): each one's t_lo and t_hi, and in
    // `hit` all ones where its line meets the volume, else 0 (t_lo and t_hi then mean nothing). The same
    // float operations lane by lane, a plane at a time, so the same intervals (tests/test_box_shadow_volume.cpp):
    // trace's packet and ordered walks ask for a tile row's eight rays together, where one ray at a time
    // was 9% of low-sun's shadowed frame (cachegrind: every lit ray of the fog meets most of the
    // poplars' long shadows).
    void interval8(const float* dx, const float* dy, const float* dz, float* t_lo, float* t_hi,
                   std::int32_t* hit) const;

    int plane_count() const { return count_; }

    // True when no view ray from `eye` can meet the shadow volume inside the region [lo, hi] (the
    // media's bounds) other than where the ray has reached the box itself and stops: the ground's
    // shadow, below it, is met only through the ground. Such a box's shadow is left out of trace's
    // intervals (every lit ray tested the ground's, for nothing).
    static bool hidden_behind_box(const Box& box, const glm::dvec3& toward_sun, const glm::dvec3& eye,
                                  const glm::dvec3& lo, const glm::dvec3& hi);

private:
    // The planes, inside where n . (x - origin) <= h, by component, so that interval() takes four at a
    // time in SIMD lanes (a plane a time, its branches and divisions were 7% of low-sun's shadowed frame).
    // Past count_ up to a whole group of four: n = 0 and h = 1, inside for every ray.
    static constexpr int kMaxPlanes = 18;  // 6 faces and 12 edges, at most
    static constexpr int kLanes = 4;
    static constexpr int kRoom = (kMaxPlanes + kLanes - 1) / kLanes * kLanes;
    alignas(16) float nx_[kRoom], ny_[kRoom], nz_[kRoom], h_[kRoom];
    int count_ = 0;
};

}  // namespace brume
