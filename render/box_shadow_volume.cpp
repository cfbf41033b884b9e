#include "render/box_shadow_volume.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {

BoxShadowVolume::BoxShadowVolume(const Box& box, const glm::dvec3& toward_sun, const glm::dvec3& origin) {
    const glm::dvec3 l = glm::normalize(toward_sun);
    const glm::dvec3 lo = box.min - origin, hi = box.max - origin;
    glm::dvec3 corners[8];
    for (int c = 0; c < 8; ++c)
        corners[c] = glm::dvec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const auto add = [&](const glm::dvec3& n, double h) {
        planes_[count_++] = Plane{float(n.x), float(n.y), float(n.z), float(h)};
    };
    // The faces the sun reaches or grazes bound the sweep (n . (x - s l) <= n . x for s >= 0); the
    // faces turned away from it do not.
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 n(0.0);
        n[a] = 1.0;
        if (l[a] >= 0.0) add(n, hi[a]);
        if (l[a] <= 0.0) add(-n, -lo[a]);
    }
    // The planes through an edge that hold l: a face of the sweep where the whole box lies on one side
    // (a silhouette edge). The box's size sets what "on the plane" means for the other corners.
    const double extent = std::max(glm::length(hi - lo), std::numeric_limits<double>::min());
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 e(0.0);
        e[a] = 1.0;
        glm::dvec3 m = glm::cross(e, l);
        const double length = glm::length(m);
        if (!(length > 1e-12)) continue;  // the edge holds l: its faces hold it too and are in above
        m /= length;
        // m along an axis: the plane is a face of the box that holds l, in above already.
        if (std::max({std::abs(m.x), std::abs(m.y), std::abs(m.z)}) > 1.0 - 1e-12) continue;
        const double tolerance = 1e-12 * extent;
        // The four edges along axis a: the corners with bit a clear, each with its partner.
        for (int c = 0; c < 8; ++c) {
            if (c & (1 << a)) continue;
            const double h = glm::dot(m, corners[c]);
            double above = -std::numeric_limits<double>::infinity(), below = std::numeric_limits<double>::infinity();
            for (const glm::dvec3& q : corners) {
                const double v = glm::dot(m, q) - h;
                above = std::max(above, v);
                below = std::min(below, v);
            }
            if (above <= tolerance) add(m, h);
            else if (below >= -tolerance) add(-m, -h);
        }
    }
}

bool BoxShadowVolume::interval(float dx, float dy, float dz, float& t_lo, float& t_hi) const {
    t_lo = -std::numeric_limits<float>::infinity();
    t_hi = std::numeric_limits<float>::infinity();
    for (int n = 0; n < count_; ++n) {
        const Plane& p = planes_[n];
        const float nd = p.nx * dx + p.ny * dy + p.nz * dz;  // n . (t d) <= h
        if (nd > 0.0f) t_hi = std::min(t_hi, p.h / nd);
        else if (nd < 0.0f) t_lo = std::max(t_lo, p.h / nd);
        else if (p.h < 0.0f) return false;  // parallel to the plane, outside it
    }
    return t_lo <= t_hi;
}

}  // namespace brume
