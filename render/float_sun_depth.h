// The spheres' optical depth toward the sun at a point, sum_k tau_k len_k(x) (render/sun_light.h), in
// float over eight spheres of a light-grid cell at a time: trace's lit boxes (the ground) take T_sun
// here, once per pixel that sees one. SunLight::optical_depth walks the same list one sphere at a time
// in double, with a branch per sphere and a square root per hit; on low-sun and ground-fog that walk was
// 9-11% of the frame. The GPU's opaque pass sums the same list in float (shaders/sun_transmittance.glsl),
// so trace's lit ground is now what ppll's is, to float rounding; the reference keeps the double walk.
// Its own grid, twice as fine as SunLight's: a point's list holds about three times the spheres above
// it, not five times.
//
// Each cell's spheres are stored relative to the cell's corner in u and v and to the cell's first
// (highest) sphere in s, so that float keeps its precision however far the scene lies from the origin:
// a query subtracts in double, then works on small numbers. A cell's list is padded to a multiple of 8
// with spheres that add nothing (radius^2 -1) and lie behind every point (sun end -inf).
#pragma once

#include "render/sun_depth_map.h"
#include "render/sun_light.h"
#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace brume {

class FloatSunDepth {
public:
    FloatSunDepth() = default;  // no shadows: every depth 0
    // `scene`'s spheres as `sun` (made from the scene) sees them. `instructions`: Best walks the lists
    // in AVX2 where the CPU has it, Portable in any x86-64's; the same float operations, so the same
    // depths bit for bit.
    FloatSunDepth(const Scene& scene, const SunLight& sun, MapInstructions instructions = MapInstructions::Best);

    // sum_k tau_k len_k(x), boxes ignored: SunLight::optical_depth(x), summed in float.
    double optical_depth(const glm::dvec3& x) const;
    // The side of a grid cell (0 when empty): about half the mean diameter of the spheres it lists.
    double cell() const { return empty_ ? 0.0 : cell_; }

private:
    bool empty_ = true;
    glm::dvec3 u_{0.0}, v_{0.0}, l_{0.0};
    double u0_ = 0.0, v0_ = 0.0, cell_ = 1.0, inverse_cell_ = 1.0;
    bool avx2_ = false;  // whether this CPU runs the AVX2 walk
    int side_ = 0;
    std::vector<std::uint32_t> first_;  // side^2 + 1 offsets, each a multiple of 8
    std::vector<double> s_ref_;          // per cell, the s its spheres' s and sun ends are relative to
    // Per listed sphere: u, v relative to the cell's corner; s and the sun end (s + r) relative to s_ref;
    // radius^2; tau.
    std::vector<float> u, v, s, sun_end, radius2, tau;
    // The outsized spheres (render/outsized_spheres.h), in no cell's list: every lookup adds their chords,
    // in double (at most kMaxOutsized square roots).
    struct Outsized {
        double u, v, s, radius2, tau;
    };
    std::vector<Outsized> outsized_;
};

}  // namespace brume
