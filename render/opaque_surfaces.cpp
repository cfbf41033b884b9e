#include "render/opaque_surfaces.h"

#include "render/ray_box.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace brume {

OpaqueSurfaces::OpaqueSurfaces(const Scene& scene, const SunLight& sun, const FloatSunDepth* float_depth)
    : boxes_(scene.boxes), lighting_(scene.lighting), sun_(sun), float_depth_(float_depth) {}

double OpaqueSurfaces::hit(const glm::dvec3& o, const glm::dvec3& d, glm::dvec3& behind) const {
    const Hit h = nearest(o, d);
    behind = radiance(h, o, d);
    return h.t;
}

OpaqueSurfaces::Hit OpaqueSurfaces::nearest(const glm::dvec3& o, const glm::dvec3& d, std::uint64_t candidates) const {
    Hit h;
    h.t = std::numeric_limits<double>::infinity();
    // The background, where no box is a candidate (and no reciprocals to take: three quotients a ray).
    if (boxes_.size() <= 64 && (boxes_.size() == 64 ? candidates : candidates & ((std::uint64_t(1) << boxes_.size()) - 1)) == 0)
        return h;
    const glm::dvec3 inv_d = inverse_direction(d);
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
        if (k < 64 && !((candidates >> k) & 1u)) continue;
        int axis = -1;
        const double t = ray_box_distance(boxes_[k], o, d, inv_d, &axis);
        if (t < h.t) {
            h.t = t;
            h.box = int(k);
            h.axis = axis;
        }
    }
    return h;
}

// From inside the box no face is crossed, so only the ambient term is reflected.
glm::dvec3 OpaqueSurfaces::box_radiance(int k, int axis, const glm::dvec3& o, const glm::dvec3& d, double t) const {
    const Box& box = boxes_[std::size_t(k)];
    if (box.diffuse == glm::dvec3(0.0)) return box.radiance;
    glm::dvec3 irradiance = lighting_.ambient;
    if (axis >= 0) {
        // The face met is the one whose outward normal opposes the ray along that axis.
        const double toward_sun = -lighting_.sun_direction[axis] / glm::length(lighting_.sun_direction);
        const double n_dot_l = d[axis] > 0.0 ? -toward_sun : toward_sun;
        if (n_dot_l > 0.0) {
            const glm::dvec3 x = o + t * d;
            const double sun = float_depth_ == nullptr ? sun_.transmittance(x, k)
                               : !sun_.shadows()      ? 1.0
                               : sun_.box_blocks(x, k) ? 0.0
                                                       : std::exp(-float_depth_->optical_depth(x));
            irradiance += lighting_.sun * (n_dot_l * sun);
        }
    }
    return box.radiance + box.diffuse * irradiance;
}

}  // namespace brume
