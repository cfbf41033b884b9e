#include "render/box_shadow_volume.h"

#include "render/simd8.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {

namespace {

// Each plane of the shadow volume of `box` (l unit, toward the sun), relative to `origin`: inside where
// n . (x - origin) <= h. `side` is true for the planes that hold l (the sweep's sides, a grazed face's
// included) and false for the faces the sun reaches, which are the box's own surface.
// A component of l this small counts as 0: the faces across it are taken as grazed (both bound the
// sweep), because the plane through a silhouette edge that holds l is then closer to a face than the
// test below can tell (its normal within 1e-12 of an axis, as it is for a component under about
// 1.4e-6), and is left out as "that face". The sweep so bounded is off the true one by at most this
// times the distance along l, 1e-3 units at 500 (the depth map's spacing is far coarser). Before
// (2026-12-06), a sun 1e-8 off the vertical left both out: the shadow ran on beside the box to
// infinity (p99.9 8.5e-3 of the peak by trace under ten posts, 1.2e-3 straight overhead).
constexpr double kGrazing = 2e-6;

template <class Plane>
void for_each_shadow_plane(const Box& box, const glm::dvec3& l, const glm::dvec3& origin, const Plane& plane) {
    const glm::dvec3 lo = box.min - origin, hi = box.max - origin;
    glm::dvec3 corners[8];
    for (int c = 0; c < 8; ++c)
        corners[c] = glm::dvec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    // The faces the sun reaches or grazes bound the sweep (n . (x - s l) <= n . x for s >= 0); the
    // faces turned away from it do not.
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 n(0.0);
        n[a] = 1.0;
        const bool grazed = std::abs(l[a]) <= kGrazing;
        if (l[a] >= 0.0 || grazed) plane(n, hi[a], grazed);
        if (l[a] <= 0.0 || grazed) plane(-n, -lo[a], grazed);
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
            if (above <= tolerance) plane(m, h, true);
            else if (below >= -tolerance) plane(-m, -h, true);
        }
    }
}

// BoxShadowVolume::interval8's lanes: a plane at a time, each lane's bound the scalar code's (the same
// products, sum and quotient, each rounded as there: no fused multiply-add, in either build below). The
// scalar code takes the planes four to a lane and the least of those at the end: minima and maxima do
// not depend on the order they are taken in (but for the sign of a zero bound, which compares and
// clips alike).
[[gnu::always_inline]] inline void intervals8(const float* nx, const float* ny, const float* nz, const float* h,
                                              int count, const float* dx, const float* dy, const float* dz,
                                              float* t_lo, float* t_hi, std::int32_t* hit) {
    using simd::Float8;
    using simd::Int8;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const Float8 x = simd::load8(dx), y = simd::load8(dy), z = simd::load8(dz);
    Float8 lo = Float8{} - inf, hi = Float8{} + inf;
    Int8 outside{};
    for (int n = 0; n < count; ++n) {
        const Float8 nd = nx[n] * x + ny[n] * y + nz[n] * z;
        const Float8 q = h[n] / nd;  // +-inf or NaN where nd = 0: not taken below
        hi = nd > 0.0f ? (q < hi ? q : hi) : hi;
        lo = nd < 0.0f ? (q > lo ? q : lo) : lo;
        if (h[n] < 0.0f) outside |= nd == 0.0f;  // parallel to a plane, outside it
    }
    simd::store8(t_lo, lo);
    simd::store8(t_hi, hi);
    simd::store8(hit, ~outside & (lo <= hi));
}

// Compiled for any x86-64, and for AVX2 (8 lanes in one register) without FMA, so both round alike.
void intervals8_portable(const float* nx, const float* ny, const float* nz, const float* h, int count,
                         const float* dx, const float* dy, const float* dz, float* t_lo, float* t_hi,
                         std::int32_t* hit) {
    intervals8(nx, ny, nz, h, count, dx, dy, dz, t_lo, t_hi, hit);
}
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2")]] void intervals8_avx2(const float* nx, const float* ny, const float* nz, const float* h,
                                             int count, const float* dx, const float* dy, const float* dz,
                                             float* t_lo, float* t_hi, std::int32_t* hit) {
    intervals8(nx, ny, nz, h, count, dx, dy, dz, t_lo, t_hi, hit);
}
#endif

}  // namespace

BoxShadowVolume::BoxShadowVolume(const Box& box, const glm::dvec3& toward_sun, const glm::dvec3& origin) {
    for (int n = 0; n < kRoom; ++n) {
        nx_[n] = ny_[n] = nz_[n] = 0.0f;
        h_[n] = 1.0f;
    }
    for_each_shadow_plane(box, glm::normalize(toward_sun), origin, [&](const glm::dvec3& n, double h, bool) {
        nx_[count_] = float(n.x);
        ny_[count_] = float(n.y);
        nz_[count_] = float(n.z);
        h_[count_] = float(h);
        ++count_;
    });
}

bool BoxShadowVolume::hidden_behind_box(const Box& box, const glm::dvec3& toward_sun, const glm::dvec3& eye,
                                        const glm::dvec3& lo, const glm::dvec3& hi) {
    // The volume is convex, so a segment from an eye outside it to a point P inside enters it once,
    // through its boundary: through a face the sun reaches, which is the box's surface (the view ray
    // stops there, at or before P), or through a side. So where the eye is outside and no side's plane
    // meets the region of the eye and `lo`-`hi` (which holds every such segment), no view ray meets
    // the shadow there before the box. Each test keeps the box where rounding could decide it.
    const glm::dvec3 region_lo = glm::min(lo, eye) - eye, region_hi = glm::max(hi, eye) - eye;
    const double scale = std::max({glm::length(region_lo), glm::length(region_hi), glm::length(box.min - eye),
                                   glm::length(box.max - eye)});
    const double tolerance = 1e-9 * scale;
    bool eye_outside = false, side_meets_region = false;
    for_each_shadow_plane(box, glm::normalize(toward_sun), eye, [&](const glm::dvec3& n, double h, bool side) {
        if (h < -tolerance) eye_outside = true;  // the eye, at 0, is on the outer side of this plane
        if (!side) return;
        double least = std::numeric_limits<double>::infinity(), most = -least;
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 corner((c & 1) ? region_hi.x : region_lo.x, (c & 2) ? region_hi.y : region_lo.y,
                                    (c & 4) ? region_hi.z : region_lo.z);
            const double v = glm::dot(n, corner) - h;
            least = std::min(least, v);
            most = std::max(most, v);
        }
        if (least <= tolerance && most >= -tolerance) side_meets_region = true;
    });
    return eye_outside && !side_meets_region;
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

void BoxShadowVolume::interval8(const float* dx, const float* dy, const float* dz, float* t_lo, float* t_hi,
                                std::int32_t* hit) const {
#if defined(__x86_64__) && defined(__GNUC__)
    if (simd::cpu_has_avx2()) return intervals8_avx2(nx_, ny_, nz_, h_, count_, dx, dy, dz, t_lo, t_hi, hit);
#endif
    intervals8_portable(nx_, ny_, nz_, h_, count_, dx, dy, dz, t_lo, t_hi, hit);
}

}  // namespace brume
