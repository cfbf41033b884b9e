// `auto` (issue 4): model no more than the frame needs. When no two spheres on screen share volume,
// compositing whole spheres back to front in power-distance order (|c - eye|^2 - r^2) is exact, with
// each sphere's chord clipped by the eye and the opaque surface, and needs no per-pixel lists; only
// frames with intersecting spheres pay for ppll. The choice is made per frame on the CPU
// (sim/sphere_overlap.h, O(n log n)).
//
// One difference remains: the compositor integrates every sphere, while ppll and the reference stop
// once transmittance falls below the scene's min_transmittance. What lies behind such a point
// contributes at most min_transmittance times its radiance, so auto is exact wherever the scene
// sets min_transmittance = 0 and within that bound otherwise.
#pragma once

#include "render/methods/method.h"
#include "render/methods/ppll.h"
#include "render/methods/sorted.h"

namespace brume {

class AutoMethod : public Method {
public:
    explicit AutoMethod(vk::Device& device);
    std::string name() const override { return "auto"; }
    bool exact() const override { return true; }
    Image render(const Scene& scene, FrameStats* stats) override;
    // Which method rendered the last frame: "ppll" or "power-sorted".
    const std::string& last_choice() const { return last_choice_; }

private:
    PpllMethod ppll_;
    SortedCompositor power_sorted_;
    std::string last_choice_;
};

}  // namespace brume
