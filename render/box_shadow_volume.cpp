#include "render/box_shadow_volume.h"

#include "render/simd8.h"

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
    for (int n = 0; n < kRoom; ++n) {
        nx_[n] = ny_[n] = nz_[n] = 0.0f;
        h_[n] = 1.0f;
    }
    const auto add = [&](const glm::dvec3& n, double h) {
        nx_[count_] = float(n.x);
        ny_[count_] = float(n.y);
        nz_[count_] = float(n.z);
        h_[count_] = float(h);
        ++count_;
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
    // Each plane n . (t d) <= h bounds t from above where n . d > 0, from below where n . d < 0, and
    // where n . d = 0 holds for every t or none. Four planes at a time: each lane's quotient is the
    // scalar division's, and a minimum or maximum does not depend on the order it is taken in, so the
    // interval is the one plane-by-plane code finds, bit for bit (tests/test_box_shadow_volume.cpp).
    using Float4 = simd::Float4;
    using Int4 = simd::Int4;
    constexpr float inf = std::numeric_limits<float>::infinity();
    Float4 lo = Float4{} - inf, hi = Float4{} + inf;
    Int4 outside{};
    for (int n = 0; n < count_; n += kLanes) {
        const Float4 nx = simd::load4(nx_ + n), ny = simd::load4(ny_ + n), nz = simd::load4(nz_ + n);
        const Float4 h = simd::load4(h_ + n);
        const Float4 nd = nx * dx + ny * dy + nz * dz;
        const Float4 q = h / nd;  // +-inf or NaN where nd = 0: not taken below
        hi = nd > 0.0f ? (q < hi ? q : hi) : hi;
        lo = nd < 0.0f ? (q > lo ? q : lo) : lo;
        outside |= (nd == 0.0f) & (h < 0.0f);
    }
    const Float4 hi2 = __builtin_shufflevector(hi, hi, 2, 3, 0, 1), lo2 = __builtin_shufflevector(lo, lo, 2, 3, 0, 1);
    const Float4 hi_pair = hi < hi2 ? hi : hi2, lo_pair = lo > lo2 ? lo : lo2;
    t_hi = std::min(hi_pair[0], hi_pair[1]);
    t_lo = std::max(lo_pair[0], lo_pair[1]);
    if ((outside[0] | outside[1] | outside[2] | outside[3]) != 0) return false;  // parallel to a plane, outside it
    return t_lo <= t_hi;
}

}  // namespace brume
