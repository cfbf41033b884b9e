// `trace`: the light model of docs/accuracy.md traced on the CPU in float, built for speed. On a
// machine whose Vulkan device is itself the CPU (lavapipe), this is the fastest exact path Brume has:
// the GPU methods pay there for rasterisation, atomics and SIMD lanes that wait for each other, which a
// tracer that walks each ray alone does not (docs/performance.md, "trace").
//
// How: the spheres are sorted near to far by a lower bound of their event distances
// (render/nearest_bounds.h) and binned into 8x8-pixel tiles (render/tile_bins.h). Each pixel takes its
// tile's spheres in that order and keeps its pending events in two sorted runs, entries and exits;
// when a sphere arrives, every pending event before its bound is final (no later sphere has an event
// before it), and every eighth sphere the final events are merged from the two runs and integrated. So
// the events are integrated in exact order, and once transmittance falls below the scene's
// min_transmittance the ray stops: the spheres behind are never intersected (at most eight too many are).
// A tile that lists at most eight spheres (one ray a pixel) walks a row's eight rays at once instead,
// one per SIMD lane (render/packet_walk.h): the same events in the same order and the same arithmetic,
// for a fraction of the per-ray cost where rays have few events; its images agree with the one-ray
// walk's to float rounding (where the compiler fuses a multiply-add in one walk and not the other).
// A tile of 9-64 spheres that cover it does likewise in an order its rows share, each lane's events
// put right by a few transposition passes and checked (render/ordered_walk.h); a ray whose order
// they could not put right walks alone. Both in the code compiled for AVX2 only: in the portable code
// the lanes cost more than they save.
//
// What differs from the reference is float arithmetic only (the same as the GPU methods' exact
// integrator, shaders/exact_integrator.glsl): the opaque surfaces are the reference's own
// (render/opaque_surfaces.h, double). With shadows, the per-sphere technique is closed form as on the
// GPU. The accurate technique reads the spheres' optical depth toward the sun from a light-space map
// built once per frame (render/sun_depth_map.h), at every event and at most every four map cells along
// a segment (closer where the depth changes fast), takes it as linear in between (a closed form), and
// cuts the box shadows (render/box_shadow_volume.h) out of each segment exactly; those pieces of a
// tile's rays are integrated together after the rays, eight at a time (render/simd8.h), since none
// depends on another. Lit boxes take the exact T_sun at the hit. Bit-identical for any thread count. A tile's work is compiled for any x86-64
// and again for AVX2 with FMA, taken where the CPU has them (TraceInstructions).
#pragma once

#include "render/image.h"
#include "render/sun_depth_map.h"
#include "render/sun_light.h"
#include "sim/scene.h"

#include <cstdint>

namespace brume {

// The instructions trace's per-pixel work is compiled for: Best takes AVX2 and FMA where the CPU has
// them (1.5-3.4x faster a frame, 2026-12-07; the packet and ordered walks, eight rays in SIMD lanes,
// run in that code only: render/fast_tracer.cpp kWalksInLanes; the images then differ from Portable's
// in float rounding, within the same bounds against the reference), Portable any x86-64's (tests hold
// the two together).
enum class TraceInstructions { Best, Portable };

// What a caller that traces frame after frame keeps between them, so that a frame reuses the memory of
// the one before: the accurate technique's sun map (up to 32 MiB; freed and allocated again, its pages
// faulted in afresh every frame). One per render that may run at the same time as another.
struct FastTraceScratch {
    SunDepthMap sun_map;
};

// How a frame's tiles were walked (FastTraceOptions::counts): by the packet walk (at most 8 spheres),
// the ordered walk (render/ordered_walk.h) or one ray at a time; and the rays of ordered tiles that
// walked alone, their order being one the row's could not be put right into. Under the accurate
// shadow technique: the sun pieces that packet rows took in their lanes, and those they handed to the
// tiles' jobs to be halved; the jobs, those and the one-ray walk's pieces.
struct FastTraceCounts {
    std::uint64_t packet_tiles = 0, ordered_tiles = 0, one_ray_tiles = 0;
    std::uint64_t ordered_rays_alone = 0;
    std::uint64_t lane_sun_pieces = 0, lane_sun_pieces_halved = 0, job_sun_pieces = 0;
};

struct FastTraceOptions {
    int threads = 0;  // 0: every usable CPU (usable_cpus, sim/usable_cpus.h)
    TraceInstructions instructions = TraceInstructions::Best;
    FastTraceScratch* scratch = nullptr;  // null: the frame allocates its own
    // Tiles of few spheres take eight rays at once (render/packet_walk.h), and so do tiles of a few
    // dozen spheres that cover them (render/ordered_walk.h), in the code compiled for AVX2 (the portable
    // code walks every ray alone: there the lanes were slower); false: every ray walks alone (the tests
    // hold them together).
    bool packets = true;
    FastTraceCounts* counts = nullptr;  // where given, how the frame's tiles were walked
    // The scene's sun (render/sun_light.h), where the caller has built it already (the frame path does,
    // for every method): a frame then builds it once, not twice (its light-space grid is a serial pass
    // over the spheres, 2% of vdb-cloud's frame on two threads). Null: the frame builds its own.
    const SunLight* sun = nullptr;
};

// The instructions `options` gives the per-pixel work on this CPU: "AVX2+FMA" or "portable", for the
// benchmarks' headers (the two differ 1.5-3.4x a frame).
const char* fast_trace_instructions(const FastTraceOptions& options = {});

// One ray per pixel centre, or the mean of camera.supersample^2 sub-pixel rays, as the reference.
// Throws std::invalid_argument for a camera with no pixels and std::logic_error for unconverted volumes.
Image render_fast_trace(const Scene& scene, const FastTraceOptions& options = {});
// The same frame written straight into rgba (camera.width * camera.height pixels of 4 floats, row by
// row, alpha 1): the frame path's upload buffer, without an Image between.
void render_fast_trace_rgba(const Scene& scene, const FastTraceOptions& options, float* rgba);

}  // namespace brume
