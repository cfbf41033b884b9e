#include "render/float_sun_depth.h"

#include "render/outsized_spheres.h"
#include "render/simd8.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {
namespace {

using simd::Float8;
using simd::Int8;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxSide = 2048;

// One cell's list from `first` (a multiple of 8) for `count` padded spheres, at the point (xu, xv, xs)
// relative to the cell: each sphere's chord above the point as SunLight::optical_depth takes it (the
// whole chord 2 half where the sphere lies wholly above, else what lies above, half - b, at least 0),
// times tau, summed lane by lane. The lists run from the sun down (by sun end): once a group's last
// sphere ends at or behind the point, so does every later one, and they add nothing (the ones in the
// group that do add exactly 0: half - b <= r - r there).
template <class Sqrt>
[[gnu::always_inline]] inline double depth_in_cell(const float* u, const float* v, const float* s, const float* sun_end,
                                                   const float* radius2, const float* tau, std::size_t first,
                                                   std::size_t count, float xu, float xv, float xs, const Sqrt& sqrt8) {
    const Float8 zero{};
    Float8 sum{};
    for (std::size_t n = first; n < first + count; n += 8) {
        const Float8 du = xu - simd::load8(u + n), dv = xv - simd::load8(v + n);
        const Float8 disc = simd::load8(radius2 + n) - (du * du + dv * dv);
        const Int8 inside = disc > zero;  // the point lies in this sphere's shadow cylinder
        const Float8 half = sqrt8(inside ? disc : zero);
        const Float8 b = xs - simd::load8(s + n);
        const Float8 above = half - b;
        const Float8 length = (-b - half >= zero) ? half + half : (above > zero ? above : zero);
        sum += inside ? simd::load8(tau + n) * length : zero;
        if (sun_end[n + 7] <= xs) break;
    }
    double total = 0.0;
    for (int l = 0; l < 8; ++l) total += double(sum[l]);
    return total;
}

#if defined(__x86_64__) && defined(__GNUC__)
struct SqrtPortable {
    [[gnu::always_inline]] Float8 operator()(const Float8& v) const { return simd::SqrtSse{}(v); }
};
[[gnu::flatten]] double depth_portable(const float* u, const float* v, const float* s, const float* sun_end,
                                       const float* radius2, const float* tau, std::size_t first, std::size_t count,
                                       float xu, float xv, float xs) {
    return depth_in_cell(u, v, s, sun_end, radius2, tau, first, count, xu, xv, xs, SqrtPortable{});
}
[[gnu::target("avx2"), gnu::flatten]] double depth_avx2(const float* u, const float* v, const float* s,
                                                       const float* sun_end, const float* radius2, const float* tau,
                                                       std::size_t first, std::size_t count, float xu, float xv,
                                                       float xs) {
    return depth_in_cell(u, v, s, sun_end, radius2, tau, first, count, xu, xv, xs, simd::SqrtAvx{});
}
#else
struct SqrtByLanes {
    Float8 operator()(const Float8& v) const {
        Float8 r;
        for (int l = 0; l < 8; ++l) r[l] = std::sqrt(v[l]);
        return r;
    }
};
double depth_portable(const float* u, const float* v, const float* s, const float* sun_end, const float* radius2,
                      const float* tau, std::size_t first, std::size_t count, float xu, float xv, float xs) {
    return depth_in_cell(u, v, s, sun_end, radius2, tau, first, count, xu, xv, xs, SqrtByLanes{});
}
#endif

}  // namespace

FloatSunDepth::FloatSunDepth(const Scene& scene, const SunLight& sun, MapInstructions instructions) {
    if (!sun.shadows() || scene.spheres.empty()) return;
    u_ = sun.grid_u();
    v_ = sun.grid_v();
    l_ = sun.toward_sun();
    // The spheres in light space; those with no medium add nothing and are left out.
    struct Disc {
        double u, v, s, r;
        float tau;
        std::uint32_t index;
    };
    std::vector<Disc> discs;
    discs.reserve(scene.spheres.size());
    for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
        const Sphere& sp = scene.spheres[k];
        if (!(sp.extinction > 0.0) || !(sp.radius > 0.0)) continue;
        discs.push_back(Disc{glm::dot(sp.center, u_), glm::dot(sp.center, v_), glm::dot(sp.center, l_), sp.radius,
                             float(sp.extinction), std::uint32_t(k)});
    }
    if (discs.empty()) return;
    empty_ = false;
    // The outsized spheres (render/outsized_spheres.h, as SunLight takes them) out of the grid, in double.
    {
        const std::vector<std::size_t> over = outsized_spheres(scene);  // in scene order, as the discs are
        std::size_t kept = 0;
        for (std::size_t k = 0, next = 0; k < discs.size(); ++k) {
            const Disc& d = discs[k];
            if (next < over.size() && over[next] == d.index) {
                outsized_.push_back(Outsized{d.u, d.v, d.s, d.r * d.r, double(d.tau)});
                ++next;
            } else {
                discs[kept++] = d;
            }
        }
        discs.resize(kept);
    }
    // The grid's extent and cell follow the listed discs.
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf, diameter_sum = 0.0;
    for (const Disc& d : discs) {
        u_lo = std::min(u_lo, d.u - d.r);
        u_hi = std::max(u_hi, d.u + d.r);
        v_lo = std::min(v_lo, d.v - d.r);
        v_hi = std::max(v_hi, d.v + d.r);
        diameter_sum += 2.0 * d.r;
    }
    // From the sun down, by the far end toward the sun (ties by scene order), once: each cell's list,
    // filled in this order, is then in it too (a sort per cell took twice the rest of the build).
    std::sort(discs.begin(), discs.end(), [](const Disc& a, const Disc& b) {
        const double ka = a.s + a.r, kb = b.s + b.r;
        return ka != kb ? ka > kb : a.index < b.index;
    });
    // Cells half the mean diameter across: a disc listed in a cell then covers about a third of it,
    // where SunLight's grid (cells a diameter across) listed five spheres for each one a point lay
    // under. A quarter diameter walked low-sun's ground 0.85x as long but took explosion's build (one
    // thread, before the tiles) from 0.7% of the frame to 1.2%; a whole diameter, 1.05x. At most
    // about 16 listings a sphere on average, so the lists stay in proportion to the scene.
    const double extent = std::max(u_hi - u_lo, v_hi - v_lo);
    const double side_by_size = std::ceil(2.0 * extent / (diameter_sum / double(discs.size())));
    const double side_by_count = std::ceil(4.0 * std::sqrt(double(discs.size())));
    side_ = int(std::clamp(std::min(side_by_size, side_by_count), 1.0, double(kMaxSide)));
    const double margin = 1e-9 * std::max(1.0, extent + std::abs(u_lo) + std::abs(v_lo));
    u0_ = u_lo - margin;
    v0_ = v_lo - margin;
    cell_ = (extent + 2.0 * margin) / double(side_);
    inverse_cell_ = 1.0 / cell_;
    avx2_ = instructions != MapInstructions::Portable && simd::cpu_has_avx2();
    // Each disc in the cells it overlaps, grown by a sliver (a point a rounding error outside a cell
    // must still find the discs that reach it): a cell whose nearest point lies within r of the centre.
    const auto for_each_cell = [&](const Disc& d, auto&& visit) {
        const double r = d.r + 1e-3 * cell_ + 1e-6 * (std::abs(d.u) + std::abs(d.v) + d.r);
        const int i0 = std::clamp(int(std::floor((d.u - r - u0_) / cell_)), 0, side_ - 1);
        const int i1 = std::clamp(int(std::floor((d.u + r - u0_) / cell_)), 0, side_ - 1);
        const int j0 = std::clamp(int(std::floor((d.v - r - v0_) / cell_)), 0, side_ - 1);
        const int j1 = std::clamp(int(std::floor((d.v + r - v0_) / cell_)), 0, side_ - 1);
        for (int j = j0; j <= j1; ++j) {
            const double cv = std::clamp(d.v, v0_ + cell_ * j, v0_ + cell_ * (j + 1)) - d.v;
            for (int i = i0; i <= i1; ++i) {
                const double cu = std::clamp(d.u, u0_ + cell_ * i, u0_ + cell_ * (i + 1)) - d.u;
                if (cu * cu + cv * cv <= r * r) visit(std::size_t(j) * std::size_t(side_) + std::size_t(i));
            }
        }
    };
    const std::size_t cells = std::size_t(side_) * std::size_t(side_);
    std::vector<std::uint32_t> count(cells + 1, 0);
    for (const Disc& d : discs) for_each_cell(d, [&](std::size_t c) { ++count[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    std::vector<std::uint32_t> listed(count[cells]);
    {
        std::vector<std::uint32_t> next(count.begin(), count.end() - 1);
        for (std::uint32_t n = 0; n < discs.size(); ++n) for_each_cell(discs[n], [&](std::size_t c) { listed[next[c]++] = n; });
    }
    // Each cell's list (from the sun down), padded.
    first_.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) first_[c + 1] = first_[c] + (count[c + 1] - count[c] + 7) / 8 * 8;
    const std::size_t size = first_[cells];
    for (std::vector<float>* a : {&u, &v, &s, &sun_end, &radius2, &tau}) a->assign(size, 0.0f);
    s_ref_.assign(cells, 0.0);
    for (std::size_t c = 0; c < cells; ++c) {
        const auto begin = listed.begin() + count[c], end = listed.begin() + count[c + 1];
        const double corner_u = u0_ + cell_ * double(c % std::size_t(side_));
        const double corner_v = v0_ + cell_ * double(c / std::size_t(side_));
        if (begin != end) s_ref_[c] = discs[*begin].s + discs[*begin].r;
        std::size_t n = first_[c];
        for (auto it = begin; it != end; ++it, ++n) {
            const Disc& d = discs[*it];
            u[n] = float(d.u - corner_u);
            v[n] = float(d.v - corner_v);
            s[n] = float(d.s - s_ref_[c]);
            sun_end[n] = float(d.s + d.r - s_ref_[c]);
            radius2[n] = float(d.r * d.r);
            tau[n] = d.tau;
        }
        for (; n < first_[c + 1]; ++n) {  // padding: outside every cylinder, behind every point
            radius2[n] = -1.0f;
            sun_end[n] = -std::numeric_limits<float>::infinity();
        }
    }
}

double FloatSunDepth::optical_depth(const glm::dvec3& x) const {
    if (empty_) return 0.0;
    const double xu = glm::dot(x, u_), xv = glm::dot(x, v_), xs = glm::dot(x, l_);
    double outsized = 0.0;  // SunLight::optical_depth's chord, for the few spheres no cell lists
    for (const Outsized& o : outsized_) {
        const double du = xu - o.u, dv = xv - o.v, disc = o.radius2 - (du * du + dv * dv);
        if (!(disc > 0.0)) continue;
        const double half = std::sqrt(disc), b = xs - o.s;
        outsized += o.tau * (-b - half >= 0.0 ? 2.0 * half : std::max(half - b, 0.0));
    }
    const int i = int(std::floor((xu - u0_) * inverse_cell_));  // a disc is listed a sliver wider than
    const int j = int(std::floor((xv - v0_) * inverse_cell_));  // its cells: rounding here is harmless
    if (i < 0 || j < 0 || i >= side_ || j >= side_) return outsized;  // outside every listed shadow cylinder
    const std::size_t c = std::size_t(j) * std::size_t(side_) + std::size_t(i);
    const std::size_t first = first_[c], count = first_[c + 1] - first;
    if (count == 0) return outsized;
    const float ru = float(xu - (u0_ + cell_ * double(i))), rv = float(xv - (v0_ + cell_ * double(j)));
    const float rs = float(xs - s_ref_[c]);
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx2_)
        return depth_avx2(u.data(), v.data(), s.data(), sun_end.data(), radius2.data(), tau.data(), first, count, ru, rv,
                          rs) +
               outsized;
#endif
    return depth_portable(u.data(), v.data(), s.data(), sun_end.data(), radius2.data(), tau.data(), first, count, ru, rv,
                          rs) +
           outsized;
}

}  // namespace brume
