// The CPU reference renderer (`--method reference`): the ground truth every GPU method is measured against.
// Double precision, analytic ray/sphere and ray/box intersection, the exact light model (docs/methods.md).
#pragma once

#include "render/image.h"
#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <vector>

namespace brume {

// How the sun term is shadowed when the scene has shadows (render/sun_light.h).
enum class ReferenceShadows {
    Exact,      // T_sun at every point, integrated by adaptive quadrature between its kinks (the model)
    PerSphere,  // T_sun once per sphere at its centre: what the GPU's per-sphere technique computes
};

struct ReferenceOptions {
    int threads = 0;           // 0: every usable CPU (usable_cpus, sim/usable_cpus.h)
    bool brute_force = false;  // test every sphere against every pixel (checks the screen-tile binning)
    ReferenceShadows shadows = ReferenceShadows::Exact;
    // Where given, render_reference adds each finished screen tile's pixels to it (relaxed), for a
    // caller that shows a long frame's progress from another thread (a shadowed frame takes seconds
    // to minutes: app/frame_progress.h). It ends at width x height.
    std::atomic<std::uint64_t>* pixels_done = nullptr;
};

// One ray per pixel centre (sim/camera_rays.h), or the mean of camera.supersample^2 sub-pixel rays. Bit-identical for any thread count, sphere order and
// brute_force setting. Throws std::invalid_argument for a camera with no pixels.
Image render_reference(const Scene& scene, const ReferenceOptions& options = {});

// Radiance along one ray (brute force over all spheres). unit_dir must be unit length.
glm::dvec3 reference_radiance(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& unit_dir,
                              const ReferenceOptions& options = {});

// Float-conditioning tolerance per pixel: the largest change of each channel when the pixel ray is
// perturbed laterally (8 directions around the ray, angle k*pi/4 in the camera right/up plane): direction
// tilted by rel_error radians and origin offset by rel_error * scale in the same lateral direction, with
// scale = max(1, |eye|, max over spheres of |centre| + radius and over boxes of |centre| + half diagonal).
// A float32 GPU renderer can only place its rays to about this precision, so near silhouettes and box
// edges its answer legitimately differs from the double-precision one by up to this much.
Image reference_tolerance(const Scene& scene, double rel_error, const ReferenceOptions& options = {});

// Depth complexity per pixel (row-major, top row first; the pixel-centre ray even when supersampled): how many spheres' clipped intervals the
// pixel ray meets, i.e. the length ppll's list for that pixel will have (twice as many surfaces).
std::vector<std::uint32_t> reference_list_lengths(const Scene& scene, const ReferenceOptions& options = {});

}  // namespace brume
