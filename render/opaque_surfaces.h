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
#include <cstring>
#include <limits>
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
    // nearest() for eight rays from `o`, ray n's direction (dx[n], dy[n], dz[n]), into out[0..8): the
    // same operations lane by lane in vectors of four doubles, so the same hits bit for bit
    // (tests/test_opaque_surfaces.cpp). One ray at a time, the slab tests' reciprocals and branches were
    // 8-11% of trace's unshadowed frame on the presets with a ground. Inline, so that trace's code
    // compiled for AVX2 takes it in AVX2.
    inline void nearest8(const glm::dvec3& o, const double* dx, const double* dy, const double* dz,
                         std::uint64_t candidates, Hit* out) const;
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

namespace opaque_detail {
using Double4 = double __attribute__((vector_size(32)));
using Mask4 = long long __attribute__((vector_size(32)));  // a lane's comparison: all ones or 0
}  // namespace opaque_detail

// ray_box_distance (render/ray_box.h) in four lanes, each step the scalar one's: a slab the ray runs
// along (d = 0) is all-or-nothing by the origin, and updates nothing; t1 > t2 swaps; the entry updates
// where it is greater (NaN never), the exit is min(tf, t2) = t2 < tf ? t2 : tf.
inline void OpaqueSurfaces::nearest8(const glm::dvec3& o, const double* dx, const double* dy, const double* dz,
                                     std::uint64_t candidates, Hit* out) const {
    using opaque_detail::Double4;
    using opaque_detail::Mask4;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const bool any = boxes_.size() > 64 ||
                     (boxes_.size() == 64 ? candidates : candidates & ((std::uint64_t(1) << boxes_.size()) - 1)) != 0;
    for (int half = 0; half < 2; ++half) {
        Double4 d[3];
        std::memcpy(&d[0], dx + 4 * half, sizeof(Double4));
        std::memcpy(&d[1], dy + 4 * half, sizeof(Double4));
        std::memcpy(&d[2], dz + 4 * half, sizeof(Double4));
        Double4 best_t = Double4{} + kInf;
        Mask4 best_box = Mask4{} - 1, best_axis = Mask4{} - 1;
        if (any) {
            Mask4 along[3];  // the ray runs along the slab: d = 0
            Double4 inv[3];
            for (int a = 0; a < 3; ++a) {
                along[a] = d[a] == 0.0;
                inv[a] = along[a] ? Double4{} : 1.0 / d[a];
            }
            for (std::size_t k = 0; k < boxes_.size(); ++k) {
                if (k < 64 && !((candidates >> k) & 1u)) continue;
                const Box& box = boxes_[k];
                Double4 tn = Double4{} - kInf, tf = Double4{} + kInf;
                Mask4 axis = Mask4{} - 1, miss = Mask4{};
                for (int a = 0; a < 3; ++a) {
                    const bool outside = o[a] < box.min[a] || o[a] > box.max[a];
                    if (outside) miss |= along[a];
                    const Double4 t1 = (box.min[a] - o[a]) * inv[a];
                    const Double4 t2 = (box.max[a] - o[a]) * inv[a];
                    const Mask4 swap = t1 > t2;
                    const Double4 lo = swap ? t2 : t1, hi = swap ? t1 : t2;
                    const Mask4 enter = (lo > tn) & ~along[a];
                    tn = enter ? lo : tn;
                    axis = enter ? Mask4{} + a : axis;
                    tf = ((hi < tf) & ~along[a]) ? hi : tf;
                }
                const Double4 t_near = tn > 0.0 ? tn : Double4{};
                const Mask4 rejected = miss | (tf < t_near) | (tn > tf);
                const Double4 t = rejected ? Double4{} + kInf : t_near;
                const Mask4 better = t < best_t;
                best_t = better ? t : best_t;
                best_box = better ? Mask4{} + (long long)k : best_box;
                best_axis = better ? (tn > 0.0 ? axis : Mask4{} - 1) : best_axis;
            }
        }
        for (int l = 0; l < 4; ++l) out[4 * half + l] = Hit{best_t[l], int(best_box[l]), int(best_axis[l])};
    }
}

}  // namespace brume
