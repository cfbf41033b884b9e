#include "render/sun_light.h"

#include "render/outsized_spheres.h"
#include "render/ray_box.h"
#include "render/simd8.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {
namespace {

using glm::dvec3;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxGridSide = 2048;

dvec3 perpendicular(const dvec3& v, const dvec3& l) { return v - glm::dot(v, l) * l; }

void add_if_inside(double t, double t0, double t1, std::vector<double>& out) {
    if (t > t0 && t < t1) out.push_back(t);
}

}  // namespace

SunLight::SunLight(const Scene& scene) : shadows_(scene.lighting.shadows), boxes_(scene.boxes) {
    const double len = glm::length(scene.lighting.sun_direction);
    if (!(len > 0.0)) shadows_ = false;  // no direction, no shadow (the reader refuses a zero direction)
    if (!shadows_) return;
    l_ = -scene.lighting.sun_direction / len;
    inverse_l_ = inverse_direction(l_);
    // Any unit vector not parallel to l makes the basis.
    const dvec3 helper = std::abs(l_.x) < 0.9 ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 1.0, 0.0);
    u_ = glm::normalize(glm::cross(l_, helper));
    v_ = glm::cross(l_, u_);

    // Each box's light-space bounds, a sliver wider than its corners' (box_blocks' quick rejection).
    for (const Box& b : boxes_) {
        BoxReach r{kInf, -kInf, kInf, -kInf, -kInf};
        for (int c = 0; c < 8; ++c) {
            const dvec3 p((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y, (c & 4) ? b.max.z : b.min.z);
            const double pu = glm::dot(p, u_), pv = glm::dot(p, v_), ps = glm::dot(p, l_);
            r.u_lo = std::min(r.u_lo, pu);
            r.u_hi = std::max(r.u_hi, pu);
            r.v_lo = std::min(r.v_lo, pv);
            r.v_hi = std::max(r.v_hi, pv);
            r.s_hi = std::max(r.s_hi, ps);
        }
        const double sliver = 1e-9 * (1.0 + glm::length(b.min) + glm::length(b.max));
        r.u_lo -= sliver;
        r.u_hi += sliver;
        r.v_lo -= sliver;
        r.v_hi += sliver;
        r.s_hi += sliver;
        box_reach_.push_back(r);
    }
    discs_.reserve(scene.spheres.size());
    for (const Sphere& s : scene.spheres)
        discs_.push_back({s.center, s.radius, s.radius * s.radius, s.extinction, glm::dot(s.center, l_) + s.radius});
    // The outsized spheres (the depth map's rule), out of the grid.
    for (const std::size_t k : outsized_spheres(scene)) {
        const Disc& d = discs_[k];
        outsized_indices_.push_back(std::uint32_t(k));
        outsized_.push_back(LightDisc{glm::dot(d.center, u_), glm::dot(d.center, v_), glm::dot(d.center, l_), d.radius2,
                                      d.tau, d.sun_end});
    }
}

void SunLight::build_grid() const {
    Grid& g = grid_;
    if (!shadows_ || discs_.empty()) return;
    // The spheres the grid lists: all but the outsized (which would set its extent and its cells).
    std::vector<std::uint32_t> listed;
    listed.reserve(discs_.size() - outsized_indices_.size());
    for (std::size_t k = 0, next = 0; k < discs_.size(); ++k) {
        if (next < outsized_indices_.size() && outsized_indices_[next] == k) {
            ++next;
            continue;
        }
        listed.push_back(std::uint32_t(k));
    }
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf;
    for (const std::uint32_t k : listed) {
        const Disc& s = discs_[k];
        const double cu = glm::dot(s.center, u_), cv = glm::dot(s.center, v_);
        u_lo = std::min(u_lo, cu - s.radius);
        u_hi = std::max(u_hi, cu + s.radius);
        v_lo = std::min(v_lo, cv - s.radius);
        v_hi = std::max(v_hi, cv + s.radius);
    }
    const double extent = std::max(u_hi - u_lo, v_hi - v_lo);
    // Cells about a sphere across, so a cell lists about as many spheres as overlap there in light space;
    // at most about 4 cells per sphere, so the grid's memory stays in proportion to the scene's.
    double mean_diameter = 0.0;
    for (const std::uint32_t k : listed) mean_diameter += 2.0 * discs_[k].radius;
    mean_diameter /= double(listed.size());
    const double side_by_size = std::ceil(extent / mean_diameter);
    const double side_by_count = std::ceil(2.0 * std::sqrt(double(listed.size()))) + 1.0;
    g.side = int(std::clamp(std::min(side_by_size, side_by_count), 1.0, double(kMaxGridSide)));
    const int side = g.side;
    // Slack on every side, so that a disc's own bound never rounds out of the grid.
    const double margin = 1e-9 * std::max(1.0, extent + std::abs(u_lo) + std::abs(v_lo));
    g.u0 = u_lo - margin;
    g.v0 = v_lo - margin;
    g.cell = (extent + 2.0 * margin) / side;

    // Each disc is listed in the cells its square overlaps, grown by a sliver: the GPU projects points in
    // float, and one a rounding error outside a cell must still find the discs that reach it.
    // (Extra candidates cost a test each and add exactly 0 to the optical depth.)
    const auto cell_range = [&](const Disc& s, int& i0, int& i1, int& j0, int& j1) {
        const double cu = glm::dot(s.center, u_), cv = glm::dot(s.center, v_);
        const double r = s.radius + 1e-3 * g.cell + 1e-6 * (std::abs(cu) + std::abs(cv) + s.radius);
        i0 = std::clamp(int(std::floor((cu - r - g.u0) / g.cell)), 0, side - 1);
        i1 = std::clamp(int(std::floor((cu + r - g.u0) / g.cell)), 0, side - 1);
        j0 = std::clamp(int(std::floor((cv - r - g.v0) / g.cell)), 0, side - 1);
        j1 = std::clamp(int(std::floor((cv + r - g.v0) / g.cell)), 0, side - 1);
    };
    // Two passes: count, then fill (a compact list per cell, in sphere order).
    const std::size_t cells = std::size_t(side) * std::size_t(side);
    g.cell_start.assign(cells + 1, 0);
    for (const std::uint32_t k : listed) {
        int i0, i1, j0, j1;
        cell_range(discs_[k], i0, i1, j0, j1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) ++g.cell_start[std::size_t(j) * side + i + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) g.cell_start[c + 1] += g.cell_start[c];
    g.cell_items.resize(g.cell_start[cells]);
    std::vector<std::uint32_t> fill(g.cell_start.begin(), g.cell_start.end() - 1);
    for (const std::uint32_t k : listed) {
        int i0, i1, j0, j1;
        cell_range(discs_[k], i0, i1, j0, j1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) g.cell_items[fill[std::size_t(j) * side + i]++] = k;
    }
    // Each cell's list from the sun down: by the sphere's far end toward the sun, dot(c, l) + r, largest
    // first (ties by index). A sphere with dot(c, l) + r <= dot(x, l) lies wholly behind x as the sun
    // sees it and adds exactly 0, and so does every sphere after it: a lookup stops there
    // (optical_depth, shaders/sun_transmittance.glsl), skipping on average half a column.
    for (std::size_t c = 0; c < cells; ++c)
        std::sort(g.cell_items.begin() + g.cell_start[c], g.cell_items.begin() + g.cell_start[c + 1],
                  [&](std::uint32_t a, std::uint32_t b) {
                      const double ka = discs_[a].sun_end, kb = discs_[b].sun_end;
                      return ka != kb ? ka > kb : a < b;
                  });
    // The same lists as light-space discs side by side, for optical_depth's walk.
    g.cell_discs.resize(g.cell_items.size());
    for (std::size_t n = 0; n < g.cell_items.size(); ++n) {
        const Disc& d = discs_[g.cell_items[n]];
        g.cell_discs[n] = LightDisc{glm::dot(d.center, u_), glm::dot(d.center, v_), glm::dot(d.center, l_), d.radius2,
                                    d.tau, d.sun_end};
    }
}

// tau times the length of the ray (xu, xv, xs) + s l (s > 0) inside the sphere `d`, in light space: the
// ray is the line (xu, xv) along s, so its distance from the sphere's axis is in u and v alone, and
// b = dot(x - c, l) is xs - cs. Through the whole sphere the length is the chord 2 sqrt(disc) itself,
// not the difference of its far and near roots (which cancels far away).
namespace {
template <class LightDisc>
double depth_in(const LightDisc& d, double xu, double xv, double xs) {
    const double du = xu - d.u, dv = xv - d.v;
    const double disc = d.radius2 - (du * du + dv * dv);
    if (!(disc > 0.0) || !(d.tau > 0.0)) return 0.0;
    const double half = std::sqrt(disc);
    const double b = xs - d.s;
    return d.tau * (-b - half >= 0.0 ? 2.0 * half : std::max(half - b, 0.0));
}
}  // namespace

double SunLight::optical_depth(const dvec3& x) const {
    if (!shadows_) return 0.0;
    const Grid& g = grid();
    if (g.side == 0) return 0.0;
    const double xu = glm::dot(x, u_), xv = glm::dot(x, v_), xs = glm::dot(x, l_);
    double depth = 0.0;
    const int i = int(std::floor((xu - g.u0) / g.cell));
    const int j = int(std::floor((xv - g.v0) / g.cell));
    if (i >= 0 && j >= 0 && i < g.side && j < g.side) {  // else outside every listed sphere's shadow cylinder
        // The lit ground asks this once per pixel of trace's frame, over every sphere above it.
        const std::size_t c = std::size_t(j) * g.side + i;
        for (std::uint32_t n = g.cell_start[c]; n < g.cell_start[c + 1]; ++n) {
            const LightDisc& d = g.cell_discs[n];
            if (d.sun_end <= xs) break;  // this sphere and the rest lie behind x (the lists' order)
            depth += depth_in(d, xu, xv, xs);
        }
    }
    for (const LightDisc& d : outsized_) depth += depth_in(d, xu, xv, xs);
    return depth;
}

void SunLight::shadow_set(const dvec3& o, const dvec3& d, double t, ShadowSet& out) const {
    out.box_blocked = false;
    out.a = out.line0 = out.line1 = 0.0;
    out.reach.clear();
    out.closest.clear();
    out.weight.clear();
    if (!shadows_) return;
    const dvec3 x = o + t * d;
    out.box_blocked = box_blocks(x);
    if (out.box_blocked) return;  // T_sun is 0 wherever the set holds: no sphere matters
    const double xu = glm::dot(x, u_), xv = glm::dot(x, v_), xs = glm::dot(x, l_);
    const double ou = glm::dot(o, u_), ov = glm::dot(o, v_), os = glm::dot(o, l_);
    const double du = glm::dot(d, u_), dv = glm::dot(d, v_), ds = glm::dot(d, l_);
    out.a = du * du + dv * dv;
    // A member: a sphere x's ray toward the sun passes through (depth_in's cases: x inside the shadow
    // cylinder and below the sphere, or inside it below the top of its chord).
    const auto take = [&](const LightDisc& disc) __attribute__((always_inline)) {
        const double eu = xu - disc.u, ev = xv - disc.v;
        const double disc2 = disc.radius2 - (eu * eu + ev * ev);
        if (!(disc2 > 0.0) || !(disc.tau > 0.0)) return;
        const double half = std::sqrt(disc2), b = xs - disc.s;
        const bool below = -b - half >= 0.0;
        if (!below && !(half - b > 0.0)) return;  // above the sphere's chord
        const double pu = ou - disc.u, pv = ov - disc.v;  // o across the sun, from the sphere's axis
        // The nearest approach to the axis (kinks()'s form); a ray along the sun keeps its distance.
        const double closest = out.a > 0.0 ? -(pu * du + pv * dv) / out.a : 0.0;
        const double hu = pu + closest * du, hv = pv + closest * dv;
        out.reach.push_back(disc.radius2 - (hu * hu + hv * hv));
        out.closest.push_back(closest);
        if (below) {  // the whole chord
            out.weight.push_back(2.0 * disc.tau);
        } else {  // from x to the top: half - (s(t) - s_k)
            out.weight.push_back(disc.tau);
            out.line0 -= disc.tau * (os - disc.s);
            out.line1 -= disc.tau * ds;
        }
    };
    const Grid& g = grid();
    if (g.side != 0) {
        const int i = int(std::floor((xu - g.u0) / g.cell));
        const int j = int(std::floor((xv - g.v0) / g.cell));
        if (i >= 0 && j >= 0 && i < g.side && j < g.side) {
            const std::size_t c = std::size_t(j) * g.side + i;
            for (std::uint32_t n = g.cell_start[c]; n < g.cell_start[c + 1]; ++n) {
                const LightDisc& disc = g.cell_discs[n];
                if (disc.sun_end <= xs) break;  // the lists' order, as optical_depth's
                take(disc);
            }
        }
    }
    for (const LightDisc& disc : outsized_) take(disc);
    while (out.weight.size() % 4 != 0) {  // lanes that add 0
        out.reach.push_back(0.0);
        out.closest.push_back(0.0);
        out.weight.push_back(0.0);
    }
}

double SunLight::optical_depth(const ShadowSet& set, double t) {
    using simd::Double4;
    const std::size_t n = set.weight.size();  // a multiple of 4
    const double* reach = set.reach.data();
    const double* closest = set.closest.data();
    const double* weight = set.weight.data();
    const Double4 zero{};
    Double4 sum{};
    // A member the point has just left (a kink's rounding) adds 0, as depth_in's clamp would.
    for (std::size_t k = 0; k < n; k += 4) {
        const Double4 e = t - simd::load4(closest + k);
        const Double4 q = simd::load4(reach + k) - set.a * e * e;
        sum += simd::load4(weight + k) * simd::sqrt4(q > zero ? q : zero);
    }
    const double depth = set.line0 + t * set.line1 + ((sum[0] + sum[1]) + (sum[2] + sum[3]));
    return std::max(depth, 0.0);
}

bool SunLight::box_blocks(const dvec3& x, int skip_box) const {
    if (boxes_.empty()) return false;
    // A box the ray meets holds a point of the same u and v as x, further toward the sun: outside the
    // box's light-space bounds (a sliver wider) the exact test below would find no hit.
    const bool bounded = box_reach_.size() == boxes_.size();
    const double xu = bounded ? glm::dot(x, u_) : 0.0, xv = bounded ? glm::dot(x, v_) : 0.0;
    const double xs = bounded ? glm::dot(x, l_) : 0.0;
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
        if (int(k) == skip_box) continue;
        if (bounded) {
            const BoxReach& r = box_reach_[k];
            if (xu < r.u_lo || xu > r.u_hi || xv < r.v_lo || xv > r.v_hi || xs > r.s_hi) continue;
        }
        if (ray_box_distance(boxes_[k], x, l_, inverse_l_) < kInf) return true;
    }
    return false;
}

double SunLight::transmittance(const dvec3& x, int skip_box) const {
    if (!shadows_) return 1.0;
    if (box_blocks(x, skip_box)) return 0.0;
    return std::exp(-optical_depth(x));
}

void SunLight::kinks(const dvec3& o, const dvec3& d, double t0, double t1, std::vector<double>& out) const {
    if (!shadows_) return;
    const dvec3 pd = perpendicular(d, l_);
    const double a = glm::dot(pd, pd);
    for (const Disc& s : discs_) {
        if (!(s.tau > 0.0)) continue;
        const dvec3 oc = o - s.center;
        // The shadow cylinder: |perp(oc) + t perp(d)| = r. Roots around the closest approach in the light's
        // plane, so that nothing cancels when the line passes far from the axis.
        if (a > 0.0) {
            const dvec3 pc = perpendicular(oc, l_);
            const double t_star = -glm::dot(pc, pd) / a;
            const dvec3 closest = pc + t_star * pd;
            const double h2 = glm::dot(closest, closest);
            if (h2 < s.radius2) {
                const double half = std::sqrt((s.radius2 - h2) / a);
                add_if_inside(t_star - half, t0, t1, out);
                add_if_inside(t_star + half, t0, t1, out);
            }
        }
        // The sphere's own surface, where the sun ray from x starts or stops being inside it.
        const double b = glm::dot(oc, d);
        const dvec3 perp = oc - b * d;
        const double disc = s.radius2 - glm::dot(perp, perp);
        if (disc > 0.0) {
            const double root = std::sqrt(disc);
            add_if_inside(-b - root, t0, t1, out);
            add_if_inside(-b + root, t0, t1, out);
        }
    }
    for (const Box& box : boxes_) {
        double lo, hi;
        if (!box_shadow_interval(box, l_, o, d, lo, hi)) continue;
        add_if_inside(lo, t0, t1, out);
        add_if_inside(hi, t0, t1, out);
    }
}

bool box_shadow_interval(const Box& box, const dvec3& l, const dvec3& o, const dvec3& d, double& t_lo,
                         double& t_hi) {
    // For each axis with l_a != 0 the box bounds s between two lines in t: s >= alpha + beta t (lower) and
    // s <= alpha + beta t (upper); s >= 0 is one more lower bound. A t is in the shadow volume exactly when
    // every lower bound is at most every upper bound (intervals on a line meet when they meet pairwise), and
    // each pair is one linear inequality in t. Axes with l_a = 0 bound t directly.
    struct Line {
        double alpha, beta;
    };
    Line lower[4];
    Line upper[3];
    int n_lower = 0, n_upper = 0;
    lower[n_lower++] = {0.0, 0.0};
    t_lo = -kInf;
    t_hi = kInf;
    for (int a = 0; a < 3; ++a) {
        if (l[a] == 0.0) {
            if (d[a] == 0.0) {
                if (o[a] < box.min[a] || o[a] > box.max[a]) return false;
                continue;
            }
            double ta = (box.min[a] - o[a]) / d[a], tb = (box.max[a] - o[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t_lo = std::max(t_lo, ta);
            t_hi = std::min(t_hi, tb);
            continue;
        }
        const Line at_min{(box.min[a] - o[a]) / l[a], -d[a] / l[a]};
        const Line at_max{(box.max[a] - o[a]) / l[a], -d[a] / l[a]};
        lower[n_lower++] = l[a] > 0.0 ? at_min : at_max;
        upper[n_upper++] = l[a] > 0.0 ? at_max : at_min;
    }
    for (int i = 0; i < n_lower; ++i) {
        for (int j = 0; j < n_upper; ++j) {
            // lower_i(t) <= upper_j(t)  <=>  c0 + c1 t <= 0
            const double c0 = lower[i].alpha - upper[j].alpha;
            const double c1 = lower[i].beta - upper[j].beta;
            if (c1 > 0.0) t_hi = std::min(t_hi, -c0 / c1);
            else if (c1 < 0.0) t_lo = std::max(t_lo, -c0 / c1);
            else if (c0 > 0.0) return false;
        }
    }
    return t_lo <= t_hi;
}

std::vector<double> sun_transmittance_at_centres(const Scene& scene) {
    std::vector<double> t(scene.spheres.size(), 1.0);
    if (!scene.lighting.shadows) return t;
    const SunLight light(scene);
    for (std::size_t k = 0; k < scene.spheres.size(); ++k) t[k] = light.transmittance(scene.spheres[k].center);
    return t;
}

}  // namespace brume
