// The sun's transmittance through the scene, T_sun (docs/accuracy.md, "Light through the smoke"), in
// double precision: the exact reference integrates it along view rays, and the per-sphere shadow
// technique takes it once at each sphere's centre (sun_transmittance_at_centres), here, so the GPU
// methods that use that technique see exactly the values the reference's per-sphere mode uses.
//
//   l = -normalize(sun_direction), pointing toward the sun;
//   T_sun(x) = 0 if the ray x + s l (s > 0) meets a box, else exp(-sum_k tau_k len_k(x)),
//   len_k(x) the length of that ray inside sphere k. With shadows off T_sun = 1.
#pragma once

#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

namespace brume {

class SunLight {
public:
    // The light's basis and the scene's spheres and boxes. The light-space grid waits for its first
    // reader (optical_depth, transmittance, the grid's accessors below), built once, safely from any
    // thread: trace's accurate technique never reads it (it reads its own depth map), and on vdb-cloud
    // (6,095 spheres) the grid, its sorted lists most of all, was 1.2% of that frame at one thread,
    // a serial 2-3% of it at two, before any tile could start.
    explicit SunLight(const Scene& scene);
    SunLight(const SunLight&) = delete;
    SunLight& operator=(const SunLight&) = delete;

    bool shadows() const { return shadows_; }
    const glm::dvec3& toward_sun() const { return l_; }

    // T_sun(x); 1 without shadows. `skip_box` (an index into scene.boxes, or -1) is the box x lies on:
    // a ray leaving a convex box through a face it lights never re-enters it.
    double transmittance(const glm::dvec3& x, int skip_box = -1) const;
    // sum_k tau_k len_k(x), boxes ignored.
    double optical_depth(const glm::dvec3& x) const;
    // True when x + s l, s > 0, meets a box other than skip_box.
    bool box_blocks(const glm::dvec3& x, int skip_box = -1) const;

    // What T_sun depends on near a point o + t d of a ray: the spheres whose shadow holds it (each
    // one's len_k as a closed form in t) and whether a box blocks the sun there. Between two
    // neighbouring points of kinks() that set cannot change (a sphere enters or leaves it only where
    // the ray crosses its shadow cylinder or its surface, a box only at its shadow volume's faces), so
    // a caller that reads T_sun at many points between them (the reference's quadrature) takes the set
    // once, at a point inside, and then pays for its members alone: not for the rest of a light-grid
    // cell's list, nor for the cells it passes. On vdb-cloud at 160x90 the reference took 0.27x of
    // its time (8.8 s to 2.3 s, before the quadrature became Gauss-Kronrod; docs/performance.md,
    // seventeenth session).
    struct ShadowSet;
    void shadow_set(const glm::dvec3& o, const glm::dvec3& d, double t, ShadowSet& out) const;
    // The spheres' optical depth toward the sun from o + t d, for a t where `set` (taken on the same
    // ray) still holds; T_sun there is 0 if set.box_blocked, else exp(-depth).
    static double optical_depth(const ShadowSet& set, double t);

    // The distances t in (t0, t1) along o + t d (d unit) where T_sun is not smooth: where the line crosses a
    // sphere's shadow cylinder (|perp_l(x - c)| = r) or a sphere's surface (where len_k starts or stops
    // counting from x), and where it enters or leaves a box's shadow volume (the box swept along -l).
    // Appended to `out`, unsorted; a few more than strictly needed do no harm.
    void kinks(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1, std::vector<double>& out) const;

    // The light-space grid, for the GPU's copy (shaders/shared.h SunGridHeader). grid_side() is 0 without
    // shadows or spheres. Cell (i, j) covers u in grid_u0 + cell * [i, i + 1), v likewise, and lists
    // cell_items()[cell_start()[j * side + i] ...  cell_start()[j * side + i + 1]), from the sun down (by
    // dot(centre, l) + radius, largest first): a lookup at x stops at the first sphere that ends
    // behind x.
    const glm::dvec3& grid_u() const { return u_; }
    const glm::dvec3& grid_v() const { return v_; }
    double grid_u0() const { return grid().u0; }
    double grid_v0() const { return grid().v0; }
    double grid_cell() const { return grid().cell; }
    int grid_side() const { return grid().side; }
    const std::vector<std::uint32_t>& cell_start() const { return grid().cell_start; }
    const std::vector<std::uint32_t>& cell_items() const { return grid().cell_items; }
    // The outsized spheres (render/outsized_spheres.h), ascending indices into scene.spheres: in no cell's
    // list, every lookup adds their chords. At most kMaxOutsized; none in the shipped presets.
    const std::vector<std::uint32_t>& outsized_indices() const { return outsized_indices_; }

    // A sphere in light space (u, v across the sun's rays, s = dot(centre, l) along them), as each
    // grid cell lists it (cell_discs_ parallels cell_items_).
    struct LightDisc {
        double u, v, s;
        double radius2;
        double tau;
        double sun_end;
    };
    // Member k's length along the sun at t: weight_k sqrt(reach_k - a (t - closest_k)^2), whole chords
    // (the point below the sphere) at weight 2 tau, the rest of a chord from inside at weight tau, with
    // -tau (s(t) - s_k) added to `line`: the optical depth is the sum plus line0 + t line1. reach_k is
    // r^2 less the squared distance of the ray's nearest approach to the sphere's shadow axis (at
    // closest_k), a the squared length of d across the sun: no cancellation far from the axis. The
    // arrays are padded to a multiple of 4 with members of weight 0 (four lanes at a time).
    struct ShadowSet {
        bool box_blocked = false;
        double a = 0.0, line0 = 0.0, line1 = 0.0;
        std::vector<double> reach, closest, weight;
    };

private:
    struct Disc {
        glm::dvec3 center;
        double radius;
        double radius2;
        double tau;
        double sun_end;  // dot(center, l) + radius: how far toward the sun the sphere reaches
    };
    bool shadows_;
    glm::dvec3 l_{0.0};
    glm::dvec3 inverse_l_{0.0};   // inverse_direction(l_), for the boxes' shadows (render/ray_box.h)
    glm::dvec3 u_{0.0}, v_{0.0};  // a basis of the plane perpendicular to l
    std::vector<Disc> discs_;     // the spheres, as the light sees them
    std::vector<std::uint32_t> outsized_indices_;  // into discs_, ascending: left out of the grid
    std::vector<LightDisc> outsized_;              // the same spheres, for optical_depth
    std::vector<Box> boxes_;
    // Per box, the bounds of its corners in light space (u, v, and s's largest), a sliver wider: a
    // point outside them is not in its shadow (box_blocks). Empty without shadows.
    struct BoxReach {
        double u_lo, u_hi, v_lo, v_hi, s_hi;
    };
    std::vector<BoxReach> box_reach_;
    // A uniform grid over the light-space plane: cell (i, j) lists the spheres whose shadow disc
    // overlaps it, so a T_sun query tests only the spheres whose shadow cylinder can contain x.
    struct Grid {
        double u0 = 0.0, v0 = 0.0, cell = 1.0;
        int side = 0;                          // 0: no shadows, or no spheres
        std::vector<std::uint32_t> cell_start;  // side^2 + 1 offsets into cell_items
        std::vector<std::uint32_t> cell_items;
        std::vector<LightDisc> cell_discs;  // cell_items' spheres, side by side: a lookup reads one run
    };
    // The grid, built on the first call (build_grid). Once it is ready a read is one load: the
    // reference asks optical_depth at every quadrature point, from every worker.
    const Grid& grid() const {
        if (!grid_ready_.load(std::memory_order_acquire))
            std::call_once(grid_once_, [this] {
                build_grid();
                grid_ready_.store(true, std::memory_order_release);
            });
        return grid_;
    }
    void build_grid() const;
    mutable std::once_flag grid_once_;
    mutable std::atomic<bool> grid_ready_{false};
    mutable Grid grid_;
};

// T_sun at each sphere's centre (the sphere's own medium included), in the order of scene.spheres; all 1
// without shadows. The per-sphere shadow technique: the sun term of each sphere is then constant.
std::vector<double> sun_transmittance_at_centres(const Scene& scene);

// The interval of t along o + t d inside the shadow volume of `box` (points x with x + s l in the box for
// some s >= 0). False when the line misses it. Closed form: a linear program in (t, s).
bool box_shadow_interval(const Box& box, const glm::dvec3& l, const glm::dvec3& o, const glm::dvec3& d, double& t_lo,
                         double& t_hi);

}  // namespace brume
