// The `soft` method: sorted spherical billboards (soft particles, Umenhoffer et al. 2006). The same
// back-to-front sort and premultiplied "over" compositing as `sorted`, but each fragment takes the
// exact chord of its pixel ray through the sphere, clipped by the eye and by the opaque surface
// (shaders/sphere_sample.glsl): no hard cuts where spheres meet geometry or contain the eye.
//
// Exact wherever the spheres along each ray do not intersect and their centre order is their order
// along the ray (e.g. disjoint depth ranges). Where spheres intersect, "over" of two separately
// attenuated spheres differs from the integral through the intersecting media, and the image still
// jumps when two intersecting particles' centre order flips (popping).
#pragma once

#include "render/methods/sorted.h"

namespace brume {

class SoftMethod : public SortedCompositor {
public:
    explicit SoftMethod(vk::Device& device) : SortedCompositor(device, Billboard::Spherical) {}
};

// `--method soft`; it takes no setting (throws std::invalid_argument on one).
std::unique_ptr<Method> make_soft_method(vk::Device& device, const std::string& setting);

}  // namespace brume
