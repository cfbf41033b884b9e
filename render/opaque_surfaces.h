// What a ray meets behind the media: the nearest box (solid, axis aligned) or the background, and the
// radiance it sends back (docs/accuracy.md): radiance + diffuse * (L_ambient + L_sun max(0, n . l) T_sun(hit)).
// In double precision, shared by the CPU tracers (render/reference.h, render/fast_tracer.h), so both see
// the same boxes to the bit; trace sums a lit face's optical depth toward the sun in float
// (render/float_sun_depth.h), as the GPU's opaque pass does.
#pragma once

#include "render/float_sun_depth.h"
#include "render/sun_light.h"
#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace brume {

class OpaqueSurfaces {
public:
    // `sun` gives T_sun at a lit face; it must outlive this object. Where `float_depth` is given (it must
    // be made from `sun` and outlive this object too), a lit face's optical depth comes from it.
    OpaqueSurfaces(const Scene& scene, const SunLight& sun, const FloatSunDepth* float_depth = nullptr);

    // The distance to the nearest box along o + t d (d unit; +inf if none), and in `behind` the radiance
    // that reaches the eye from there (the background where no box is met).
    double hit(const glm::dvec3& o, const glm::dvec3& d, glm::dvec3& behind) const;

    // The same in two steps, for a tracer whose ray may stop in the media before it gets there (trace:
    // the lit face's T_sun, a walk over the spheres above it, was 4-8% of a shadowed preset's frame):
    // the nearest box, then the radiance from it.
    struct Hit {
        double t = 0.0;  // +inf if no box is met
        int box = -1;    // -1: the background
        int axis = -1;
    };
    // Only the boxes k < 64 whose bit k `candidates` holds are tested (a caller that knows which boxes
    // its rays may meet: trace, per tile), and every box past the 64th.
    Hit nearest(const glm::dvec3& o, const glm::dvec3& d, std::uint64_t candidates = ~std::uint64_t(0)) const;
    glm::dvec3 radiance(const Hit& hit, const glm::dvec3& o, const glm::dvec3& d) const {
        return hit.box >= 0 ? box_radiance(hit.box, hit.axis, o, d, hit.t) : lighting_.background;
    }

private:
    // The radiance of box k hit at distance t through a face of `axis` (-1: from inside, no face).
    glm::dvec3 box_radiance(int k, int axis, const glm::dvec3& o, const glm::dvec3& d, double t) const;

    std::vector<Box> boxes_;
    Lighting lighting_;
    const SunLight& sun_;
    const FloatSunDepth* float_depth_;
};

}  // namespace brume
