#include "render/fast_tracer.h"

#include "render/box_shadow_volume.h"
#include "render/compensated_sum.h"
#include "render/float_sun_depth.h"
#include "render/nearest_bounds.h"
#include "render/opaque_surfaces.h"
#include "render/ordered_walk.h"
#include "render/packet_walk.h"
#include "render/pixel_hull.h"
#include "render/sun_depth_map.h"
#include "render/sun_jobs.h"
#include "render/simd8_math.h"
#include "render/sun_light.h"
#include "sim/scene_file.h"
#include "render/tile_bins.h"
#include "sim/camera_rays.h"
#include "sim/parallel_for.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

// 8x8 pixels: smoke spheres cover a few to a few tens of pixels, and a pixel tests every sphere its
// tile lists, so a small tile wastes fewer tests; the bins cost little at this size.
constexpr std::uint32_t kTile = 8;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Four floats in one SSE register (render/simd8.h): the running sums an event changes, and the
// radiance they add, step together, one lane per sum, each lane rounding as the scalar code it
// replaces did. Lane 0 holds sigma_t where a sum has it, and 0 elsewhere.
using simd::Float4;
using simd::Int4;  // a lane mask: 0 or all ones
using simd::Double4;
using simd::sqrt4;

// What a sphere's events add and remove beyond {tau, tau * albedo} (sigma_t and sigma_s, kept apart:
// all a scene without shadows or emission reads, 16 bytes a sphere, so that a large scene's random
// reads by sphere index stay in cache): the scattering the sun lights under the per-sphere technique,
// {0, tau * albedo * T_sun(centre)} (else the same as sigma_s), and the emission, {0, tau * emission}.
struct alignas(32) LitMedium {
    Float4 sun_scatter;
    Float4 emission;
};
static_assert(sizeof(LitMedium) == 32);

// A sphere as one tile lists it: what the chord test needs, its centre relative to the eye (so that
// float keeps the precision where the rays are), copied beside the tile's other spheres so that a pixel
// reads its candidates from one short array instead of the whole scene's.
struct TileSphere {
    float cx, cy, cz, r2;
    float c_minus_r2;
    std::uint32_t bound_bits;  // float(nearest bound), the watermark
    std::uint32_t sphere;
    std::uint32_t pad;
};

// A tile's spheres, and for each of its pixels the ones its ray meets (or, with supersampling, whose
// padded pixel rectangle, render/tile_bins.h, holds it), in the tile's order (near to far by bound):
// pixel p of the tile (p = y * kTile + x) takes spheres[items[first[p]] ...  items[first[p] +
// count[p] - 1]]. A pixel so walks only the spheres that reach it, without a test (and a mispredicted
// branch) for the others.
struct TileLists {
    std::vector<TileSphere> spheres;
    std::uint32_t first[kTile * kTile + 1];
    std::uint32_t count[kTile * kTile];
    std::vector<std::uint32_t> items;
    std::vector<std::uint64_t> hits;  // per tile sphere, a bit per pixel its ray meets (list_tile's)
};

// A tile's pixel-centre rays (one a pixel: no supersampling), by tile pixel p = y * kTile + x: unit
// directions in double, as the opaque surfaces and the light take them, and in float, as the tracer
// does; each component apart, so that eight neighbours load as one SIMD value (render/packet_walk.h).
struct alignas(32) TileRays {
    double x[kTile * kTile], y[kTile * kTile], z[kTile * kTile];
    float fx[kTile * kTile], fy[kTile * kTile], fz[kTile * kTile];
    dvec3 direction(int p) const { return dvec3(x[p], y[p], z[p]); }
};

// The squared distance by which the ray t (dx, dy, dz) passes inside the sphere: r^2 less the squared
// distance of closest approach; the ray meets the sphere's volume where it is positive. The walk's
// test; list_tile takes it in eight lanes by the same operations, where the compiler may fuse a
// multiply-add differently: a chord a float's width long can then be listed and skipped by the walk
// (no change) or left out (images within 1.04e-7 of the peak of the scalar test's).
inline float chord_discriminant(const TileSphere& m, float dx, float dy, float dz, float& b) {
    b = m.cx * dx + m.cy * dy + m.cz * dz;  // distance of closest approach
    const float px = m.cx - b * dx, py = m.cy - b * dy, pz = m.cz - b * dz;
    return m.r2 - (px * px + py * py + pz * pz);
}

#if defined(__x86_64__) && defined(__GNUC__)
static_assert(sizeof(TileSphere) == 8 * sizeof(float), "chords8 reads a sphere's fields eight floats apart");

// The one-ray walk's chords of eight listed spheres at once, spheres list[items[0, batch)], a lane
// each (the lanes past `batch` repeat the last one): [start, end] along the ray t (dx, dy, dz), the
// start clipped to the eye and the end to t_opaque, as the walk's scalar steps take them (the same
// operations lane by lane: trace's images at every preset, with shadows and without, came out the same
// bytes). A lane whose ray misses its sphere gets end 0 <= start, which the walk skips as an empty
// chord. Only in code compiled for AVX2 (its gathers). One sphere at a time, each chord's square root
// and division waited in line for the last: the lanes took vdb-cloud's unshadowed frame to 0.80-0.84x
// and plume's to 0.71-0.86x (docs/performance.md, eighteenth session).
[[gnu::always_inline]] inline void chords8(const TileSphere* list, const std::uint32_t* items, std::size_t batch,
                                           float dx, float dy, float dz, float t_opaque, float* start_out,
                                           float* end_out) {
    alignas(32) std::int32_t first_field[8];
    for (std::size_t l = 0; l < 8; ++l)
        first_field[l] = std::int32_t(items[std::min(l, batch - 1)] * (sizeof(TileSphere) / sizeof(float)));
    const simd::Int8 index = simd::load8(first_field);
    const simd::GatherAvx2 gather;
    const float* const base = &list[0].cx;
    const simd::Float8 cx = gather.one(base, index), cy = gather.one(base + 1, index), cz = gather.one(base + 2, index);
    const simd::Float8 r2 = gather.one(base + 3, index), c_minus_r2 = gather.one(base + 4, index);
    // chord_discriminant, lane by lane.
    const simd::Float8 b = cx * dx + cy * dy + cz * dz;
    const simd::Float8 px = cx - b * dx, py = cy - b * dy, pz = cz - b * dz;
    const simd::Float8 disc = r2 - (px * px + py * py + pz * pz);
    const simd::Float8 zero{}, opaque = zero + t_opaque;
    const simd::Int8 meets = disc > zero;
    const simd::Float8 s = simd::SqrtAvx{}(meets ? disc : zero);
    const simd::Float8 q = b > zero ? b + s : b - s;  // |q| >= s > 0 where the ray meets the sphere
    const simd::Float8 ta = q, tb = c_minus_r2 / q;
    // std::min and std::max as the scalar steps take them: (b < a ? b : a), (a < b ? b : a).
    const simd::Float8 near = tb < ta ? tb : ta, far = ta < tb ? tb : ta;
    simd::store8(start_out, near < zero ? zero : near);  // media holding the eye count from the eye
    simd::store8(end_out, meets ? (opaque < far ? opaque : far) : zero);
}
#endif

// e^y for |y| < 87 (within float's normal range): simd::exp_reduced's polynomial, 2^n through the
// exponent bits.
[[gnu::always_inline]] inline float exp_in_range(float y) {
    float n;
    const float p = simd::exp_reduced(y, n);
    return p * std::bit_cast<float>(std::uint32_t(int(n) + 127) << 23);
}

// exp(y) for y <= 0, to about 2 ulp, inline: a call to expf per segment keeps the integrator's state
// in memory across the call (the ABI clobbers every SIMD register).
[[gnu::always_inline]] inline float exp_nonpositive(float y) {
    if (!(y > -87.0f)) return 0.0f;  // below float's normal range (and -inf); NaN never reaches here
    return exp_in_range(y);
}

// A segment of optical depth x >= 0 and length len: its transmittance e^-x and its weight
// len (1 - e^-x) / x (the GPU's one_minus_exp_over_x, shaders/medium.glsl). Below x = 1/8 both come
// from the series of (1 - e^-x) / x (simd::phi_series), e^-x as 1 - x phi, one multiply-add, to
// float's rounding: no exponential for the thin segments, most of vdb-cloud's and the fogs'. Against
// exp and the quotient for every segment (one thread, in turn): vdb-cloud's unshadowed frame 0.89-0.93x,
// bench scale's smoke clouds 0.82-0.91x; the shadowed presets and the fogs, whose packet walks
// take the same lane by lane (simd::segment_transmittance8), within the noise. Images within 1.1e-6
// of the peak of before.
[[gnu::always_inline]] inline void segment_light(float x, float len, float& transmittance, float& weight) {
    if (x < 0.125f) {
        const float phi = simd::phi_series(x);
        transmittance = 1.0f - x * phi;
        weight = len * phi;
    } else {
        transmittance = exp_nonpositive(-x);
        weight = len * ((1.0f - transmittance) / x);
    }
}

// An event key: the distance's float bits (distances are >= +0, so the bits order like the floats) over
// sphere * 2 + is_exit. Unique per ray, so the order is total.
std::uint64_t event_key(float t, std::uint32_t sphere, bool exit) {
    return (std::uint64_t(std::bit_cast<std::uint32_t>(t)) << 32) | (std::uint64_t(sphere) << 1) | (exit ? 1u : 0u);
}
float key_distance(std::uint64_t key) { return std::bit_cast<float>(std::uint32_t(key >> 32)); }


using simd::Float8;
using simd::Int8;
using simd::load8;

// The accurate technique's pieces and their integrals (render/sun_jobs.h).
using sun_jobs::kSunMaxPieces;
using sun_jobs::kSunPieceCells;
using sun_jobs::kSunPieceThinDepth;
using sun_jobs::kSunPieceThinWiden;
using sun_jobs::piece_integral8;
using sun_jobs::SunJobs;

// A ray integrates its final events at every kFlushEvery-th sphere it lists, not at each (radiance):
// how many are final at a sphere is what the branch predictor cannot know. bench scale, ms at 1,000 /
// 10,000 / 100,000 spheres: 8 gave 72-77 / 183-184 / 489-494 and 16 gave 82-83 / 180-183 / 491-494 in
// one sitting, 4 gave 75-78 / 185-187 / 500-506 in the one before.
constexpr std::size_t kFlushEvery = 8;

class FastTracer {
public:
    // Pending events in order, run[head, size - 1), between a floor (0, below or equal to every key) at
    // the front and a sentinel above every key at the back, so that neither the merge of two runs nor
    // an insertion needs a bounds test. New keys come in from the back; what is final leaves from the
    // front. What was integrated, run[kFloor, head), stays: it lies below any new key (its keys were under a
    // mark that the new one is not), so an insertion never passes it, and a ray adds at most one key per
    // sphere it lists, for which reset() makes room.
    // The run is written through a pointer into memory that reset() sized, not by push_back, which
    // tested the size and capacity at each insertion (layers at 2 layers, 800x600: 2.5% a frame).
    // The floor is seven keys deep, so that the run's last eight keys, sentinel included, always lie in
    // memory that it owns (insert<true>'s two windows).
    struct SortedRun {
        static constexpr std::uint64_t kSentinel = ~std::uint64_t(0);  // no key reaches it (t is finite)
        static constexpr std::size_t kFloor = 7;
        std::vector<std::uint64_t> storage;
        std::uint64_t* run = nullptr;
        std::size_t size = 0;
        std::size_t head = kFloor;

        void reset(std::size_t spheres) {
            // The floor, the sentinel, a key per sphere, and the slot insert<true> writes past the
            // sentinel.
            if (storage.size() < spheres + kFloor + 2) storage.resize(spheres + kFloor + 2);
            run = storage.data();
            std::fill(run, run + kFloor, std::uint64_t(0));
            run[kFloor] = kSentinel;
            size = kFloor + 1;
            head = kFloor;
        }
        std::uint64_t front() const { return run[head]; }
        // kWide (code compiled for AVX2): a key that goes among the run's last three keys (nine
        // insertions in ten on vdb-cloud and explosion, whose exits mostly land one or two places from
        // the back) is placed by one compare and two blends of the last four keys as a vector, without
        // a branch on how far it goes; one that goes among the last seven, by the four before them
        // too. The scalar loop's exit, after a varying count, was mispredicted about once an
        // insertion (8.5% of vdb-cloud's frame in its two lines, perf): vdb-cloud took 0.87x, and
        // the second vector a further 0.97-0.98x on plume and vdb-cloud, whose exits land further
        // back. The same run either way (docs/performance.md).
        template <bool kWide>
        [[gnu::always_inline]] void insert(std::uint64_t key) {
            if constexpr (kWide) {
                using U64x4 = std::uint64_t __attribute__((vector_size(32)));
                std::uint64_t* const last4 = run + (size - 4);
                U64x4 v1;
                std::memcpy(&v1, last4, sizeof v1);
                const U64x4 k = U64x4{} + key;
                const U64x4 above1 = v1 > k;
                const U64x4 next1 = __builtin_shufflevector(v1, v1, 1, 2, 3, 3);
                const U64x4 next_above1 = __builtin_shufflevector(above1, above1, 1, 2, 3, 3);
                if (above1[0] == 0) {
                    U64x4 out1 = next_above1 ? k : next1;
                    out1 = above1 ? v1 : out1;
                    std::memcpy(last4 + 1, &out1, sizeof out1);
                    ++size;
                    return;
                }
                U64x4 v0;
                std::memcpy(&v0, last4 - 4, sizeof v0);
                const U64x4 above0 = v0 > k;
                if (above0[0] == 0) {
                    const U64x4 next0 = __builtin_shufflevector(v0, v1, 1, 2, 3, 4);
                    const U64x4 next_above0 = __builtin_shufflevector(above0, above1, 1, 2, 3, 4);
                    U64x4 out0 = next_above0 ? k : next0;
                    out0 = above0 ? v0 : out0;
                    std::memcpy(last4 - 3, &out0, sizeof out0);
                    std::memcpy(last4 + 1, &v1, sizeof v1);  // every key of the last four moves up
                    ++size;
                    return;
                }
            }
            std::size_t i = size++;
            run[i] = kSentinel;
            for (; run[i - 1] > key; --i) run[i] = run[i - 1];
            run[i] = key;
        }
    };
    // One worker's buffers for a ray: its pending entries and exits, and its box shadows (accurate
    // technique).
    struct RayScratch {
        SortedRun entries, exits;
        std::vector<float> shadows;
        std::vector<float> lane_shadows[kTile];  // the packet walk's, a lane's each (radiance_row)
    };

    // `sun_map` is built again here when the scene takes accurate shadows (in its own memory). `sun`, where
    // given, is the scene's (the frame path's, built for the GPU methods); else the tracer makes its own.
    // `position_of`: the position of each sphere (by scene index) in the tracer's per-sphere arrays
    // (memory_order); the bins, the tiles' lists and the events name spheres by position.
    FastTracer(const Scene& scene, const std::vector<std::uint32_t>& position_of, int threads, SunDepthMap& sun_map,
               const SunLight* sun, MapInstructions map_instructions)
        : own_sun_(sun ? std::nullopt : std::optional<SunLight>(std::in_place, scene)),
          sun_(sun ? *sun : *own_sun_),
          float_depth_(lit_boxes(scene) ? FloatSunDepth(scene, sun_, map_instructions) : FloatSunDepth()),
          opaque_(scene, sun_, &float_depth_),
          sun_map_(sun_map),
          eye_(scene.camera.position),
          min_transmittance_(float(scene.render.min_transmittance)),
          accurate_shadows_(sun_.shadows() && scene.render.shadow_technique == ShadowTechnique::Accurate) {
        const std::vector<double> centre_sun = sun_.shadows() && !accurate_shadows_
                                                   ? sun_transmittance_at_centres(scene)
                                                   : std::vector<double>(scene.spheres.size(), 1.0);
        plain_ = !sun_.shadows();
        if (accurate_shadows_) {
            sun_map_.build(scene, sun_, eye_, threads, SunDepthMap::kDefaultMaxVertices, map_instructions);
            // Only the boxes whose shadow reaches the media: a shadow elsewhere (the ground's, below it)
            // falls where no view segment has anything to light.
            dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
            for (const Sphere& sp : scene.spheres) {
                lo = glm::min(lo, sp.center - dvec3(sp.radius));
                hi = glm::max(hi, sp.center + dvec3(sp.radius));
            }
            const dvec3 l = sun_.toward_sun();
            for (const Box& box : scene.boxes) {
                double s_from, s_to;
                if (!shadow_reaches(box, l, lo, hi, s_from, s_to)) continue;
                // Nor those whose shadow in the media is met only through the box (the ground's,
                // where smoke dips below it): a view ray stops at the box first.
                if (BoxShadowVolume::hidden_behind_box(box, l, eye_, lo, hi)) continue;
                // Where in the image its rays may meet the shadow within the media's bounds: the box
                // swept from s_from to s_to, the hull of its two ends (a tile whose rays all miss it
                // skips its intervals: on fog-bank, 5 boxes, they were 4% of the frame).
                dvec3 corners[16];
                for (int c = 0; c < 16; ++c)
                    corners[c] = dvec3((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                                       (c & 4) ? box.max.z : box.min.z) -
                                 ((c & 8) ? s_to : s_from) * l;
                PixelRect rect;
                if (!hull_pixel_rect(corners, 16, scene.camera, scene.camera.width, scene.camera.height, rect)) continue;
                shadow_volumes_.emplace_back(box, l, eye_);
                shadow_rects_.push_back(rect);
                // And the hull of those corners' projections (where all lie in front of the eye), a
                // pixel wider, as the rectangle is: a slanted shadow's rectangle holds many tiles
                // its hull does not reach.
                glm::dvec2 projected[16];
                shadow_hulls_.push_back(project_to_pixels(corners, 16, scene.camera, scene.camera.width,
                                                          scene.camera.height, projected)
                                            ? PixelHull(projected, 16, 1.0)
                                            : PixelHull());
            }
        }
        // Each box's pixels: the rectangle of its corners' projection (the whole image where a corner is
        // not in front of the eye), which holds every pixel whose rays, sub-pixel rays included, may meet it.
        for (const Box& box : scene.boxes) {
            dvec3 corners[8];
            for (int c = 0; c < 8; ++c)
                corners[c] = dvec3((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                                   (c & 4) ? box.max.z : box.min.z);
            PixelRect rect{0, 0, 0, 0};
            if (!hull_pixel_rect(corners, 8, scene.camera, scene.camera.width, scene.camera.height, rect))
                rect = PixelRect{0, 0, 0, 0};  // no pixel's ray meets it
            box_rects_.push_back(rect);
        }
        const std::size_t n = scene.spheres.size();
        extinction_scatter_.resize(n);
        lit_media_.resize(n);
        geometry_.resize(n);
        // What the tracer keeps of sphere k, at its position p; true when it emits. In scene order, the
        // writes scattered: read scattered, the spheres (about 100 bytes each) took 1.8 times as long at
        // 1,000,000 (perf).
        const auto take = [&](std::size_t k) {
            const std::uint32_t p = position_of[k];
            const Sphere& s = scene.spheres[k];
            const dvec3 c = s.center - eye_;
            geometry_[p] = TileSphere{float(c.x), float(c.y), float(c.z), float(s.radius * s.radius),
                                      float(glm::dot(c, c) - s.radius * s.radius), 0u, std::uint32_t(p), 0u};
            Float4& sigma = extinction_scatter_[p];
            LitMedium& m = lit_media_[p];
            sigma[0] = float(s.extinction);
            m.sun_scatter[0] = 0.0f;
            m.emission[0] = 0.0f;
            for (int a = 0; a < 3; ++a) {
                sigma[a + 1] = float(s.extinction * s.albedo[a]);
                m.sun_scatter[a + 1] = float(s.extinction * s.albedo[a] * centre_sun[k]);
                m.emission[a + 1] = float(s.extinction * s.emission[a]);
            }
            return s.emission != dvec3(0.0);
        };
        // In chunks over the threads (a million spheres took 50 ms on one).
        constexpr std::size_t kChunk = 4096;
        const std::size_t chunks = (n + kChunk - 1) / kChunk;
        std::vector<std::uint8_t> emits(chunks, 0);
        parallel_for(chunks, threads, [&](std::size_t chunk, int) {
            for (std::size_t k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k)
                if (take(k)) emits[chunk] = 1;
        });
        emits_ = std::find(emits.begin(), emits.end(), 1) != emits.end();
        if (emits_) plain_ = false;
        const Lighting& l = scene.lighting;
        const double sun_len = glm::length(l.sun_direction);
        sun_unit_ = sun_len > 0.0 ? l.sun_direction / sun_len : dvec3(0.0);
        ambient_ = l.ambient;
        lighting_sun_ = l.sun;
    }

    // The tile's lists (TileLists) from its bin entries (pairs of sphere and float bound bits,
    // render/tile_bins.h), near to far by bound; `rects` are the spheres' pixel rectangles, (x0, y0)
    // the tile's corner; `rays`, the ray of each of its pixels, or null with supersampling (then every pixel of a rectangle lists its sphere). Two
    // passes, so each pixel's list keeps the tile's order: the chord tests, a row of the sphere's
    // rectangle at a time in SIMD lanes (one pixel at a time, list_tile was 12% of explosion's
    // shadowed frame in a profile that kept it apart), into a bit per pixel and the pixels' counts; then each sphere into the lists of the
    // pixels its bits name. Whether a ray meets a sphere was the tracer's most mispredicted branch
    // after the event order's; here it is arithmetic.
    void list_tile(const std::uint32_t* entries, std::size_t count, const std::vector<PixelRect>& rects, int x0,
                   int y0, const TileRays* rays, TileLists& out) const {
        out.spheres.resize(count);
        out.hits.resize(count);
        // Per pixel, the spheres its ray meets; a row of eight pixels a SIMD value (Int8 lanes of 0 or
        // -1 added, as counts go down by -1).
        alignas(32) std::int32_t counts[kTile * kTile] = {};
        const Float8 lane{0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};
        for (std::size_t n = 0; n < count; ++n) {
            const std::uint32_t k = entries[2 * n];
            TileSphere& m = out.spheres[n];
            m = geometry_[k];
            m.bound_bits = entries[2 * n + 1];
            const PixelRect& r = rects[k];
            const int ya = std::max(r.y0 - y0, 0), yb = std::min(r.y1 - y0, int(kTile));
            const int xa = std::max(r.x0 - x0, 0), xb = std::min(r.x1 - x0, int(kTile));
            // The rectangle's columns in the row, as lanes and as bits.
            const Int8 columns = (lane >= float(xa)) & (lane < float(xb));
            const int column_bits = xb > xa ? ((1 << xb) - 1) & ~((1 << xa) - 1) : 0;
            std::uint64_t hits = 0;
            for (int y = ya; y < yb; ++y) {
                const int row = y * int(kTile);
                Int8 hit = columns;
                if (rays) {
                    // chord_discriminant in eight lanes (the walk takes it again for each sphere listed).
                    const Float8 dx = load8(rays->fx + row), dy = load8(rays->fy + row), dz = load8(rays->fz + row);
                    const Float8 b = m.cx * dx + m.cy * dy + m.cz * dz;
                    const Float8 px = m.cx - b * dx, py = m.cy - b * dy, pz = m.cz - b * dz;
                    hit &= (m.r2 - (px * px + py * py + pz * pz)) > 0.0f;
                }
                hits |= std::uint64_t(unsigned(simd::mask8(hit) & column_bits)) << row;
                simd::store8(counts + row, simd::load8(counts + row) - hit);
            }
            out.hits[n] = hits;
        }
        out.first[0] = 0;
        for (std::uint32_t p = 0; p < kTile * kTile; ++p) {
            out.count[p] = std::uint32_t(counts[p]);
            out.first[p + 1] = out.first[p] + std::uint32_t(counts[p]);
        }
        out.items.resize(out.first[kTile * kTile]);
        std::uint32_t next[kTile * kTile];
        std::copy(out.first, out.first + kTile * kTile, next);
        // Each sphere into the lists of the pixels it reaches, in the tile's order.
        for (std::size_t n = 0; n < count; ++n)
            for (std::uint64_t hits = out.hits[n]; hits != 0; hits &= hits - 1)
                out.items[next[std::countr_zero(hits)]++] = std::uint32_t(n);
    }

    // The opaque surfaces of a tile row's eight rays (`boxes`: tile_box_mask), eight at a time: none where
    // the tile has no candidate box (and the scene no box past the 64th, which every tile tests).
    void row_opaque_hits(const TileRays& tile_rays, int row, std::uint64_t boxes, OpaqueSurfaces::Hit* out) const {
        const int first = row * int(kTile);
        if (boxes == 0 && box_rects_.size() <= 64) {
            std::fill(out, out + kTile, OpaqueSurfaces::Hit{kInfinity, -1, -1});
            return;
        }
        static_assert(kTile == 8, "nearest8 takes a row of eight rays");
        opaque_.nearest8(eye_, tile_rays.x + first, tile_rays.y + first, tile_rays.z + first, boxes, out);
    }

    // Radiance toward the eye along unit direction d, from the tile's spheres items[0, count) names,
    // listed near to far by their bounds.
    // kPlain: a scene without shadows or emission (plain_), whose integrator needs only sigma_t and
    // sigma_s: a third of the work per event.
    // With accurate shadows the sun's light is not in the answer: the ray's lit pieces go to `jobs`, for
    // tile pixel `pixel` (resolve_sun_jobs adds their light to the pixel's sum).
    // `boxes`: the boxes the ray may meet (tile_box_mask).
    // kWide: code compiled for AVX2 (SortedRun::insert).
    // `known_opaque`: the ray's opaque surface where the caller found it already (row_opaque_hits), else null.
    template <bool kPlain, bool kWide>
    dvec3 radiance(const dvec3& d, const TileSphere* list, const std::uint32_t* items, std::size_t count,
                   RayScratch& scratch, SunJobs& jobs, std::uint32_t pixel, std::uint64_t boxes,
                   const OpaqueSurfaces::Hit* known_opaque = nullptr) const {
        // The opaque surface's distance now, its radiance (a lit face's T_sun) only if the ray gets there.
        const OpaqueSurfaces::Hit opaque = known_opaque ? *known_opaque : opaque_.nearest(eye_, d, boxes);
        const float t_opaque = float(opaque.t);
        const float dx = float(d.x), dy = float(d.y), dz = float(d.z);

        const double cos_theta = glm::dot(sun_unit_, d);
        const dvec3 sun_phase_d = lighting_sun_ * (3.0 / (16.0 * 3.14159265358979323846) * (1.0 + cos_theta * cos_theta));
        Ray ray;
        for (int a = 0; a < 3; ++a) {
            ray.sun_phase[a + 1] = float(sun_phase_d[a]);
            ray.source[a + 1] = float(ambient_[a] + sun_phase_d[a]);
            ray.ambient[a + 1] = float(ambient_[a]);
        }
        ray.d = d;
        if (!kPlain && accurate_shadows_) {
            ray.map = sun_map_.ray(d);
            ray.t_opaque = t_opaque;
            ray.shadow_scratch = &scratch.shadows;  // box_shadows fills it once a segment is lit
            ray.sun_jobs = &jobs;
            ray.ray_id = std::uint32_t(jobs.rays.size());
            ray.pixel = pixel;
            jobs.rays.push_back(ray.map);
        }

        // The pending events, in two sorted runs merged as they leave: entries arrive in about bound order,
        // so an entry goes in at or near the back of its run, and an exit need not pass the entries
        // that wait before it (one run of both cost a sixth of the frame in moves, cachegrind).
        SortedRun& entries = scratch.entries;
        SortedRun& exits = scratch.exits;
        entries.reset(count);
        exits.reset(count);
        // Integrates, in order, every pending event before `mark`; false once the ray stopped.
        const auto flush = [&](std::uint64_t mark, State& st) {
            for (;;) {
                // Which run leads is a coin toss to the branch predictor: arithmetic, not a branch.
                const std::uint64_t a = entries.front(), b = exits.front();
                const std::size_t entry_first = a < b;
                const std::uint64_t next = std::min(a, b);
                if (next >= mark) return true;
                entries.head += entry_first;
                exits.head += 1 - entry_first;
                if (!integrate<kPlain>(st, ray, next)) return false;
            }
        };
        State st;
        alignas(32) float lane_start[8], lane_end[8];  // kWide: chords8's, for spheres n - n % 8 on
        for (std::size_t n = 0; n < count; ++n) {
#if defined(__x86_64__) && defined(__GNUC__)
            if constexpr (kWide)
                if (n % 8 == 0)
                    chords8(list, items + n, std::min<std::size_t>(8, count - n), dx, dy, dz, t_opaque, lane_start,
                            lane_end);
#endif
            const TileSphere& m = list[items[n]];
            const std::uint32_t k = m.sphere;
            const std::uint32_t bound_bits = m.bound_bits;
            const float bound = std::bit_cast<float>(bound_bits);
            if (bound >= t_opaque) break;  // this sphere and every later one lie behind the opaque surface
            // No later sphere has an event before this one's bound: the pending events before it are final.
            // They are integrated at every kFlushEvery-th sphere only: how many there are is what the
            // branch predictor cannot know, and the order does not wait for them (an insertion never
            // passes a smaller key); a ray that stops walks at most that many spheres too far.
            if (n % kFlushEvery == 0) {
                const std::uint64_t mark = std::uint64_t(bound > 0.0f ? bound_bits : 0u) << 32;
                if (!flush(mark, st)) return st.color();
            }
            // Chord of the ray t d through the sphere (the reference's sphere_chord, in float). Without
            // supersampling list_tile listed only the spheres this ray meets, by the same test.
            float start, end;
            if constexpr (kWide) {
                start = lane_start[n % 8];
                end = lane_end[n % 8];
            } else {
                float b;
                const float disc = chord_discriminant(m, dx, dy, dz, b);
                if (!(disc > 0.0f)) continue;
                const float s = std::sqrt(disc);
                const float q = b > 0.0f ? b + s : b - s;  // |q| >= s > 0
                const float ta = q, tb = m.c_minus_r2 / q;
                start = std::max(std::min(ta, tb), 0.0f);  // media holding the eye count from the eye
                end = std::min(std::max(ta, tb), t_opaque);
            }
            if (!(end > start)) continue;
            entries.insert<kWide>(event_key(start, k, false));
            exits.insert<kWide>(event_key(end, k, true));
        }
        if (!flush(SortedRun::kSentinel, st)) return st.color();
        return st.color() + double(st.transmittance) * opaque_.radiance(opaque, eye_, d);
    }

    bool plain() const { return plain_; }

    // Whether the scene has a box whose faces reflect light (the lit ground): FloatSunDepth serves them.
    static bool lit_boxes(const Scene& scene) {
        return std::any_of(scene.boxes.begin(), scene.boxes.end(), [](const Box& b) { return b.diffuse != dvec3(0.0); });
    }

    // The packet walk (render/packet_walk.h), for a tile whose rays are one per pixel and whose spheres
    // are at most packet::kMaxSpheres: the tile's spheres as it reads them, from its
    // bin entries as list_tile takes them, each with the tile's pixels that its rectangle covers (which
    // list_tile would test), (x0, y0) the tile's corner. No pixel lists: every lane tests every sphere.
    void packet_spheres(const std::uint32_t* entries, std::size_t count, const std::vector<PixelRect>& rects, int x0,
                        int y0, packet::Spheres& out) const {
        out.sigma_t = out.sigma_r = out.sigma_g = out.sigma_b = Float8{};
        out.sun_r = out.sun_g = out.sun_b = out.emission_r = out.emission_g = out.emission_b = Float8{};
        walk_spheres(entries, count, rects, x0, y0, out);
    }

    // The ordered walk (render/ordered_walk.h), for a tile whose rays are one per pixel and whose spheres
    // are more than the packet walk takes, up to packet::kMaxOrderedSpheres: as packet_spheres, and
    // each rank's place in the tile.
    void ordered_spheres(const std::uint32_t* entries, std::size_t count, const std::vector<PixelRect>& rects, int x0,
                         int y0, packet::OrderedSpheres& out) const {
        walk_spheres(entries, count, rects, x0, y0, out);
        for (std::size_t n = 0; n < count; ++n) out.by_rank[out.rank[n]] = std::uint8_t(n);
    }

    // The packet walk's light for this scene (as radiance's: kPlain where plain_).
    packet::Light packet_light() const {
        return plain_ ? packet::Light::kPlain : accurate_shadows_ ? packet::Light::kAccurate : packet::Light::kPerSphere;
    }

    // The radiance of tile row `row`'s eight pixels by the packet walk, into sums (by tile pixel, as
    // radiance of each would give it); `boxes`, `scratch` and `jobs` as radiance's; under the accurate
    // technique the row's lit segments go through `lit_steps` to lit_steps_light (`gather` reads the sun
    // map there, `counts` counts its pieces). kLight:
    // packet_light() (a template argument, so that each light's ray set-up is radiance's to the
    // operation: where L_sun P(theta) has no other use, its sum with L_ambient fuses).
    template <packet::Light kLight, class Gather>
    void radiance_row(const packet::Spheres& spheres, const TileRays& tile_rays, int row, std::uint64_t boxes,
                      RayScratch& scratch, SunJobs& jobs, packet::LitSteps& lit_steps, const Gather& gather,
                      FastTraceCounts& counts, dvec3* sums) const {
        OpaqueSurfaces::Hit opaque[kTile];
        packet::Rays rays;
        row_rays<kLight>(tile_rays, row, boxes, rays, opaque);
        // Sphere n tested by lane l where its rectangle covers the lane's pixel, as list_tile tests it.
        const Int8 lane{0, 1, 2, 3, 4, 5, 6, 7};
        for (int n = 0; n < spheres.count; ++n) {
            const bool row_covered = row >= spheres.rows[n][0] && row < spheres.rows[n][1];
            rays.listed[n] = (lane >= spheres.columns[n][0]) & (lane < spheres.columns[n][1]) & (row_covered ? -1 : 0);
        }
        const packet::Result r = walk_packet<kLight>(spheres, rays, lit_steps);
        finish_row(r, opaque, tile_rays, row, Int8{}, sums);
        if constexpr (kLight == packet::Light::kAccurate)
            lit_steps_light(lit_steps, tile_rays, row, rays, scratch, jobs, gather, counts, sums);
    }

    // The radiance of tile row `row`'s eight pixels by the ordered walk (render/ordered_walk.h), into
    // sums, as radiance_row's; the lanes it leaves to the one-ray walk come back as bits (lane l: bit l),
    // their sums not written.
    template <packet::Light kLight, class Gather>
    unsigned radiance_ordered_row(const packet::OrderedSpheres& spheres, const TileRays& tile_rays, int row,
                                  std::uint64_t boxes, RayScratch& scratch, SunJobs& jobs,
                                  packet::OrderedEvents& events, packet::LitSteps& lit_steps, const Gather& gather,
                                  FastTraceCounts& counts, dvec3* sums) const {
        OpaqueSurfaces::Hit opaque[kTile];
        packet::Rays rays;
        row_rays<kLight>(tile_rays, row, boxes, rays, opaque);
        Int8 failed{};
        const packet::Result r =
            packet::ordered_walk<kLight>(spheres, rays, row, min_transmittance_, events, failed, gather, lit_steps);
        finish_row(r, opaque, tile_rays, row, failed, sums);
        if constexpr (kLight == packet::Light::kAccurate)
            lit_steps_light(lit_steps, tile_rays, row, rays, scratch, jobs, gather, counts, sums);
        unsigned bits = 0;
        for (int l = 0; l < int(kTile); ++l) bits |= failed[l] ? 1u << l : 0u;
        return bits;
    }

private:
    // What both packet walks read of a tile's spheres (packet::Spheres, packet::OrderedSpheres): each
    // one's chord test, its pixel rectangle in the tile, its rank by scene index (the events' order
    // among equal distances), and by rank its media (sigma_t and sigma_s, the per-sphere technique's
    // sun-lit sigma_s, tau * emission).
    template <class Out>
    void walk_spheres(const std::uint32_t* entries, std::size_t count, const std::vector<PixelRect>& rects, int x0,
                      int y0, Out& out) const {
        out.count = int(count);
        out.emits = false;
        for (std::size_t n = 0; n < count; ++n) {
            const std::uint32_t k = entries[2 * n];
            const TileSphere& m = geometry_[k];
            out.cx[n] = m.cx;
            out.cy[n] = m.cy;
            out.cz[n] = m.cz;
            out.r2[n] = m.r2;
            out.c_minus_r2[n] = m.c_minus_r2;
            const PixelRect& r = rects[k];
            out.columns[n][0] = r.x0 - x0;
            out.columns[n][1] = r.x1 - x0;
            out.rows[n][0] = r.y0 - y0;
            out.rows[n][1] = r.y1 - y0;
            std::uint32_t rank = 0;
            for (std::size_t o = 0; o < count; ++o) rank += entries[2 * o] < k ? 1u : 0u;
            out.rank[n] = rank;
            const Float4& sigma = extinction_scatter_[k];
            out.sigma_t[rank] = sigma[0];
            out.sigma_r[rank] = sigma[1];
            out.sigma_g[rank] = sigma[2];
            out.sigma_b[rank] = sigma[3];
            const LitMedium& lit = lit_media_[k];
            out.sun_r[rank] = lit.sun_scatter[1];
            out.sun_g[rank] = lit.sun_scatter[2];
            out.sun_b[rank] = lit.sun_scatter[3];
            out.emission_r[rank] = lit.emission[1];
            out.emission_g[rank] = lit.emission[2];
            out.emission_b[rank] = lit.emission[3];
            out.emits |= lit.emission[1] != 0.0f || lit.emission[2] != 0.0f || lit.emission[3] != 0.0f;
        }
    }

    // Tile row `row`'s eight rays as the packet walks read them, but for the spheres each lane tests
    // (the packet walk's `listed`), into `rays`; their opaque surfaces into `opaque`.
    template <packet::Light kLight>
    void row_rays(const TileRays& tile_rays, int row, std::uint64_t boxes, packet::Rays& rays,
                  OpaqueSurfaces::Hit* opaque) const {
        const int first = row * int(kTile);
        rays.dx = load8(tile_rays.fx + first);
        rays.dy = load8(tile_rays.fy + first);
        rays.dz = load8(tile_rays.fz + first);
        // The opaque surfaces: none where the tile has no candidate box (and the scene no box past the
        // 64th, which every tile tests).
        float t_opaque[kTile];
        row_opaque_hits(tile_rays, row, boxes, opaque);
        for (int l = 0; l < int(kTile); ++l) t_opaque[l] = float(opaque[l].t);
        rays.t_opaque = load8(t_opaque);
        // L_ambient + L_sun P(theta), in double as radiance takes it (the same operations), four lanes
        // at a time, the halves put together in registers (through memory, an 8-lane load of two
        // 4-lane stores stalls).
        Float4 source[3][2], sun_phase[3][2] = {};
        for (int h = 0; h < 2; ++h) {
            Double4 dx, dy, dz;
            std::memcpy(&dx, tile_rays.x + first + 4 * h, sizeof dx);
            std::memcpy(&dy, tile_rays.y + first + 4 * h, sizeof dy);
            std::memcpy(&dz, tile_rays.z + first + 4 * h, sizeof dz);
            const Double4 cos_theta = (sun_unit_.x * dx + sun_unit_.y * dy) + sun_unit_.z * dz;
            const Double4 phase = 3.0 / (16.0 * 3.14159265358979323846) * (1.0 + cos_theta * cos_theta);
            if constexpr (kLight == packet::Light::kPlain) {
                source[0][h] = __builtin_convertvector(ambient_.x + lighting_sun_.x * phase, Float4);
                source[1][h] = __builtin_convertvector(ambient_.y + lighting_sun_.y * phase, Float4);
                source[2][h] = __builtin_convertvector(ambient_.z + lighting_sun_.z * phase, Float4);
                continue;
            }
            const Double4 sun_r = lighting_sun_.x * phase, sun_g = lighting_sun_.y * phase,
                          sun_b = lighting_sun_.z * phase;
            source[0][h] = __builtin_convertvector(ambient_.x + sun_r, Float4);
            source[1][h] = __builtin_convertvector(ambient_.y + sun_g, Float4);
            source[2][h] = __builtin_convertvector(ambient_.z + sun_b, Float4);
            sun_phase[0][h] = __builtin_convertvector(sun_r, Float4);
            sun_phase[1][h] = __builtin_convertvector(sun_g, Float4);
            sun_phase[2][h] = __builtin_convertvector(sun_b, Float4);
        }
        const auto lanes = [](const Float4 (&halves)[2]) {
            return __builtin_shufflevector(halves[0], halves[1], 0, 1, 2, 3, 4, 5, 6, 7);
        };
        rays.source_r = lanes(source[0]);
        rays.source_g = lanes(source[1]);
        rays.source_b = lanes(source[2]);
        rays.sun_phase_r = lanes(sun_phase[0]);
        rays.sun_phase_g = lanes(sun_phase[1]);
        rays.sun_phase_b = lanes(sun_phase[2]);
        rays.ambient_r = Float8{} + float(ambient_.x);
        rays.ambient_g = Float8{} + float(ambient_.y);
        rays.ambient_b = Float8{} + float(ambient_.z);
    }

    // A walked row's pixels into sums, each with what lies behind its media; not the lanes of `skip`.
    void finish_row(const packet::Result& r, const OpaqueSurfaces::Hit* opaque, const TileRays& tile_rays, int row,
                    const Int8& skip, dvec3* sums) const {
        for (int l = 0; l < int(kTile); ++l) {
            if (skip[l]) continue;
            const int p = row * int(kTile) + l;
            dvec3 color(r.r[l], r.g[l], r.b[l]);
            if (!r.stopped[l])
                color += double(r.transmittance[l]) * opaque_.radiance(opaque[l], eye_, tile_rays.direction(p));
            sums[p] = color;
        }
    }

public:

    // Which of the first 64 boxes the rays of pixels [x0, x1) x [y0, y1) may meet (bit k for box k): a
    // tile tests only those (on ground-fog, 5 boxes, a stone's box lies in a few tiles).
    std::uint64_t tile_box_mask(int x0, int y0, int x1, int y1) const { return rect_mask(box_rects_, x0, y0, x1, y1); }

    // The packet walk with as many event slots as the tile's spheres need.
    template <packet::Light kLight>
    packet::Result walk_packet(const packet::Spheres& spheres, const packet::Rays& rays,
                               packet::LitSteps& lit_steps) const {
        const int count = spheres.count;
        return count <= 1   ? packet::walk<2, kLight>(spheres, rays, min_transmittance_, lit_steps)
               : count <= 2 ? packet::walk<4, kLight>(spheres, rays, min_transmittance_, lit_steps)
               : count <= 4 ? packet::walk<8, kLight>(spheres, rays, min_transmittance_, lit_steps)
                            : packet::walk<16, kLight>(spheres, rays, min_transmittance_, lit_steps);
    }

    // Which of the first 64 box shadow volumes the rays of pixels [x0, x1) x [y0, y1) may meet within
    // the media's bounds (bit n for volume n).
    std::uint64_t tile_shadow_mask(int x0, int y0, int x1, int y1) const {
        std::uint64_t mask = rect_mask(shadow_rects_, x0, y0, x1, y1);
        for (std::uint64_t m = mask; m != 0; m &= m - 1) {
            const int n = std::countr_zero(m);
            if (!shadow_hulls_[std::size_t(n)].may_reach(x0, y0, x1, y1)) mask &= ~(std::uint64_t(1) << n);
        }
        return mask;
    }

private:
    // Bit n for each of the first 64 rectangles that overlaps pixels [x0, x1) x [y0, y1).
    static std::uint64_t rect_mask(const std::vector<PixelRect>& rects, int x0, int y0, int x1, int y1) {
        std::uint64_t mask = 0;
        for (std::size_t n = 0; n < std::min<std::size_t>(rects.size(), 64); ++n) {
            const PixelRect& r = rects[n];
            if (r.x0 < x1 && x0 < r.x1 && r.y0 < y1 && y0 < r.y1) mask |= std::uint64_t(1) << n;
        }
        return mask;
    }

    // Whether box's shadow volume (the box swept along -l) meets the axis-aligned box [lo, hi]: is there
    // an s >= 0 with box - s l overlapping it on every axis? Each axis bounds s to an interval; their
    // intersection is [s_lo, s_hi].
    static bool shadow_reaches(const Box& box, const dvec3& l, const dvec3& lo, const dvec3& hi, double& s_lo,
                               double& s_hi) {
        s_lo = 0.0;
        s_hi = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            // box.min - s l <= hi and box.max - s l >= lo, on axis a.
            const double from = box.min[a] - hi[a], to = box.max[a] - lo[a];  // s l_a in [from, to]
            if (l[a] == 0.0) {
                if (from > 0.0 || to < 0.0) return false;
                continue;
            }
            double s0 = from / l[a], s1 = to / l[a];
            if (s0 > s1) std::swap(s0, s1);
            s_lo = std::max(s_lo, s0);
            s_hi = std::min(s_hi, s1);
        }
        return s_lo <= s_hi;
    }

    // The intervals of t in [0, t_opaque) along eye + t d inside some box's shadow volume (T_sun = 0
    // there), sorted and merged, as pairs (lo, hi) in `out`. Per box, its bounding planes (render/box_shadow_volume.h).
    // Only the volumes `mask` holds (tile_shadow_mask) and any past the 64th: the others' intervals lie
    // outside the media, where no segment is lit.
    void box_shadows(const dvec3& d, float t_opaque, std::vector<float>& out, std::uint64_t mask) const {
        out.clear();
        const float dx = float(d.x), dy = float(d.y), dz = float(d.z);
        for (std::size_t n = 0; n < shadow_volumes_.size(); ++n) {
            if (n < 64 && !((mask >> n) & 1u)) continue;
            float lo, hi;
            if (!shadow_volumes_[n].interval(dx, dy, dz, lo, hi)) continue;
            lo = std::max(lo, 0.0f);
            hi = std::min(hi, t_opaque);
            if (!(hi > lo)) continue;
            out.push_back(lo);
            out.push_back(hi);
        }
        sort_and_merge_shadows(out);
    }

    // Pairs (lo, hi) sorted by their start, overlaps merged, in place.
    static void sort_and_merge_shadows(std::vector<float>& out) {
        if (out.size() <= 2) return;
        // Sort the pairs by their start (insertion: a ray meets few shadows), then merge overlaps in place.
        const std::size_t pairs = out.size() / 2;
        for (std::size_t n = 1; n < pairs; ++n)
            for (std::size_t m = n; m > 0 && out[2 * m] < out[2 * m - 2]; --m) {
                std::swap(out[2 * m], out[2 * m - 2]);
                std::swap(out[2 * m + 1], out[2 * m - 1]);
            }
        std::size_t kept = 1;
        for (std::size_t n = 1; n < pairs; ++n) {
            if (out[2 * n] <= out[2 * kept - 1]) {
                out[2 * kept - 1] = std::max(out[2 * kept - 1], out[2 * n + 1]);
            } else {
                out[2 * kept] = out[2 * n];
                out[2 * kept + 1] = out[2 * n + 1];
                ++kept;
            }
        }
        out.resize(2 * kept);
    }

    struct Ray {
        dvec3 d;
        // In lanes 1-3 (Float4): L_ambient + L_sun P(theta), the unshadowed L_s of this ray; L_sun P(theta);
        // L_ambient. Lane 0 is 0.
        Float4 source{};
        Float4 sun_phase{};
        Float4 ambient{};
        // The accurate technique: the ray in the optical-depth map, and where its box shadows go once
        // it meets media (box_shadows, up to the opaque surface at t_opaque).
        SunDepthMap::Ray map{};
        float t_opaque = 0.0f;
        std::vector<float>* shadow_scratch = nullptr;
        // Where its lit pieces go (sun_jobs), as ray `ray_id` of the tile, for tile pixel `pixel`.
        SunJobs* sun_jobs = nullptr;
        std::uint32_t ray_id = 0, pixel = 0;
    };
    // Front-to-back state of one ray: running sums of the media it is in (shaders/exact_integrator.glsl).
    struct State {
        Float4 radiance{};  // lanes 1-3
        float transmittance = 1.0f;
        Float4 sigma{};      // {sigma_t, sigma_s}
        Float4 sigma_sun{};  // {0, the sun-lit part of sigma_s} (the per-sphere technique)
        Float4 sigma_e{};    // {0, sum tau_k e_k}
        // Each sum above is sum + error: the sums stepped by TwoSum, which keeps each step's rounding
        // exactly in error (compensated_step), so leaving a dense sphere inside a thin medium gives the thin
        // medium back, not a residue of the dense one's rounding (render/compensated_sum.h).
        Float4 sigma_sum{}, sigma_error{}, sun_sum{}, sun_error{}, emission_sum{}, emission_error{};
        int inside = 0;
        float t_prev = 0.0f;
        // The accurate technique: the ray's box shadows, sorted pairs (lo, hi), once shadows_ready (its
        // first lit segment), and the first one not yet passed; the end of the last piece it gave its
        // jobs (SunJobs::add), which the next piece shares if it starts there.
        bool shadows_ready = false;
        SunJobs::RayEnd sun_end;
        const float* shadows = nullptr;
        std::size_t shadow_count = 0;
        std::size_t shadow_next = 0;
        float sigma_t() const { return sigma[0]; }
        dvec3 color() const { return dvec3(radiance[1], radiance[2], radiance[3]); }
    };

    // A walked row's rays as the one-ray walk's sun pieces take them (add_sun_pieces, add_sun_job): each
    // lane with its own ray in the map, box shadows and state, its jobs for its own pixel (the jobs of
    // the row's rays interleave; each pixel's keep their order, and so its sums).
    struct RowSunRays {
        Ray lanes[kTile];
        State states[kTile];
        RowSunRays(const FastTracer& t, const TileRays& tile_rays, int first, const packet::Rays& rays,
                   RayScratch& scratch, SunJobs& jobs) {
            for (int l = 0; l < int(kTile); ++l) {
                Ray& ray = lanes[l];
                ray.d = tile_rays.direction(first + l);
                ray.map = t.sun_map_.ray(ray.d);
                ray.t_opaque = rays.t_opaque[l];
                ray.shadow_scratch = &scratch.lane_shadows[l];
                ray.sun_jobs = &jobs;
                ray.ray_id = std::uint32_t(jobs.rays.size());
                ray.pixel = std::uint32_t(first + l);
                jobs.rays.push_back(ray.map);
            }
        }
    };

    // box_shadows for a tile row's eight rays (`rays`, their float directions and opaque distances), the
    // lanes of `lanes` only, into each lane's scratch and state (ready_box_shadows'): each volume's
    // intervals for the eight at once (BoxShadowVolume::interval8, the same intervals), then each
    // lane's as box_shadows takes them.
    void row_box_shadows(RowSunRays& row, const Int8& lanes, const packet::Rays& rays, std::uint64_t mask) const {
        alignas(32) float dx[kTile], dy[kTile], dz[kTile];
        simd::store8(dx, rays.dx);
        simd::store8(dy, rays.dy);
        simd::store8(dz, rays.dz);
        for (int l = 0; l < int(kTile); ++l)
            if (lanes[l]) row.lanes[l].shadow_scratch->clear();
        alignas(32) float lo[kTile], hi[kTile];
        alignas(32) std::int32_t hit[kTile];
        for (std::size_t n = 0; n < shadow_volumes_.size(); ++n) {
            if (n < 64 && !((mask >> n) & 1u)) continue;
            shadow_volumes_[n].interval8(dx, dy, dz, lo, hi, hit);
            for (int l = 0; l < int(kTile); ++l) {
                if (!lanes[l] || !hit[l]) continue;
                const float a = std::max(lo[l], 0.0f), b = std::min(hi[l], row.lanes[l].t_opaque);
                if (!(b > a)) continue;
                row.lanes[l].shadow_scratch->push_back(a);
                row.lanes[l].shadow_scratch->push_back(b);
            }
        }
        for (int l = 0; l < int(kTile); ++l) {
            if (!lanes[l]) continue;
            std::vector<float>& out = *row.lanes[l].shadow_scratch;
            sort_and_merge_shadows(out);
            State& st = row.states[l];
            st.shadows = out.data();
            st.shadow_count = out.size() / 2;
            st.shadows_ready = true;
        }
    }

    // The accurate technique's sun light over a walked row's lit segments (packet::LitSteps), into the
    // row's pixel sums, eight lanes at a time: the pieces that add_sun_pieces cuts (box shadows
    // included), each one's depth toward the sun read at its end (and at its start where the lane's
    // piece before did not end there), and its closed form, as resolve_sun_jobs takes a job's. Where
    // the one-ray walk's jobs are written down one by one, then read back, a step's eight lanes are cut
    // at once and share the lookups and the closed form (fog-bank's and ground-fog's frames are mostly
    // such pieces). In three passes (SunJobs::LanePieces), so that neither the lookups nor the closed
    // forms wait on the cutting's branches: the pieces, the depths at their points, then the integrals.
    // A piece whose light times its change of depth calls for halving goes to the tile's jobs, as the
    // one-ray walk's pieces do, and sun_jobs::refine_pieces halves it there.
    template <class Gather>
    void lit_steps_light(const packet::LitSteps& steps, const TileRays& tile_rays, int row, const packet::Rays& rays,
                         RayScratch& scratch, SunJobs& jobs, const Gather& gather, FastTraceCounts& counts,
                         dvec3* sums) const {
        Int8 lit_lanes{};
        for (int k = 0; k < steps.steps; ++k) lit_lanes |= steps.lit[k];
        if (!packet::any(lit_lanes)) return;
        RowSunRays row_rays(*this, tile_rays, row * int(kTile), rays, scratch, jobs);
        // Each lane's box shadow ahead: the first of its ray's intervals (box_shadows) not yet passed,
        // [shadow_lo, shadow_hi), or +inf where none is left (none at all where the tile's mask is empty).
        const Float8 zero{};
        const float inf = std::numeric_limits<float>::infinity();
        Float8 shadow_lo = zero + inf, shadow_hi = zero + inf;
        if (jobs.shadow_mask != 0 || shadow_volumes_.size() > 64) {
            row_box_shadows(row_rays, lit_lanes, rays, jobs.shadow_mask);
            for (int l = 0; l < int(kTile); ++l)
                if (lit_lanes[l]) {
                    const State& st = row_rays.states[l];
                    if (st.shadow_count > 0) {
                        shadow_lo[l] = st.shadows[0];
                        shadow_hi[l] = st.shadows[1];
                    }
                }
        }
        SunJobs::LanePieces& pieces = jobs.lanes;
        pieces.clear();
        // The pieces, as add_sun_pieces cuts them: from p, to the segment's end b, p + max_piece or the
        // next edge of a box shadow, whichever is nearest, while p < b; each one's end a point to look
        // up, and its start too where a lane's piece before did not end there. Pieces in a shadow add
        // nothing.
        const float max_piece = kSunPieceCells * sun_map_.cell(), thin_max = kSunPieceThinWiden * max_piece;
        Float8 last_t = zero - 1.0f;  // each lane's last piece's end
        for (int k = 0; k < steps.steps; ++k) {
            const Int8 lit = steps.lit[k];
            if (!packet::any(lit)) continue;
            const Float8 b = steps.b[k];
            // Each lane's longest piece: longer in thin media (kSunPieceThinWiden). NaN-free: sigma_t > 0
            // on a lit step, and 0 gives +inf, clamped.
            Float8 lane_piece = kSunPieceThinDepth / steps.sigma_t[k];
            lane_piece = lane_piece < thin_max ? lane_piece : zero + thin_max;
            lane_piece = lane_piece > max_piece ? lane_piece : zero + max_piece;
            const Float8 even_cut = (b - steps.a[k]) / kSunMaxPieces;  // kSunMaxPieces pieces at most
            lane_piece = lane_piece > even_cut ? lane_piece : even_cut;
            Float8 p = steps.a[k];
            Int8 active = lit & (p < b);
            while (packet::any(active)) {
                // The shadows that end at or before p passed (State::shadow_next: a lane's next one).
                for (Int8 passed = active & (shadow_hi <= p); packet::any(passed); passed = active & (shadow_hi <= p))
                    for (int l = 0; l < int(kTile); ++l)
                        if (passed[l]) {
                            State& st = row_rays.states[l];
                            const bool more = ++st.shadow_next < st.shadow_count;
                            shadow_lo[l] = more ? st.shadows[2 * st.shadow_next] : inf;
                            shadow_hi[l] = more ? st.shadows[2 * st.shadow_next + 1] : inf;
                        }
                const Int8 shadowed = shadow_lo <= p;
                Float8 q = p + lane_piece;
                q = q < b ? q : b;
                const Float8 edge = shadowed ? shadow_hi : shadow_lo;
                q = edge < q ? edge : q;
                q = q > p ? q : b;  // a piece shorter than float's step: end the segment (adds nothing)
                const Int8 lit_piece = active & ~shadowed;
                if (packet::any(lit_piece)) {
                    const Int8 shared = last_t == p;
                    pieces.add(k, p, q, lit_piece, shared, packet::any(lit_piece & ~shared));
                    last_t = lit_piece ? q : last_t;
                }
                p = active ? q : p;
                active &= p < b;
            }
        }
        // The depths at the points.
        Float8 u0, du, v0, dv, s0, ds;
        for (int l = 0; l < int(kTile); ++l) {
            const SunDepthMap::Ray& m = row_rays.lanes[l].map;
            u0[l] = m.u0;
            du[l] = m.du;
            v0[l] = m.v0;
            dv[l] = m.dv;
            s0[l] = m.s0;
            ds[l] = m.ds;
        }
        if (sun_map_.empty())
            std::fill(pieces.depth.begin(), pieces.depth.begin() + std::ptrdiff_t(8 * pieces.points), 0.0f);
        else
            for (std::size_t i = 0; i < pieces.points; ++i) {
                const Float8 t = load8(pieces.t.data() + 8 * i);  // as SunJobs::add_point's lattice coordinates
                simd::store8(pieces.depth.data() + 8 * i,
                             sun_map_.optical_depth8(u0 + t * du, v0 + t * dv, s0 + t * ds, gather));
            }
        // The integrals: piece_integral8's closed form and halving test, each lane's light times its
        // integral summed in float over up to kPiecesInFloat pieces, then added in double (a double sum
        // per piece, six conversions and six additions in one chain, was 2-4% of fog-bank's and
        // low-sun's frames; a float sum of 16 positive terms is within 1e-6 of its own, and the images
        // within 1.1e-7 of the peak).
        Float8 last_depth = zero;  // at each lane's last piece's end
        Double4 total[3][2] = {};
        Float8 partial[3] = {};
        constexpr std::size_t kPiecesInFloat = 16;
        Int8 taken{}, halved{};  // the pieces each lane took, and handed to the jobs (FastTraceCounts)
        for (std::size_t i = 0; i < pieces.count; ++i) {
            const SunJobs::LanePiece& piece = pieces.pieces[i];
            const int k = piece.step;
            const Float8 od_q = load8(pieces.depth.data() + 8 * piece.end_point);
            const Float8 p = load8(piece.p), q = load8(piece.q);
            const Int8 active = simd::load8(piece.active), shared = simd::load8(piece.shared);
            const Float8 od_p = shared ? last_depth : load8(pieces.depth.data() + 8 * piece.start_point);
            last_depth = active ? od_q : last_depth;
            const Float8 sigma_t = steps.sigma_t[k], weight = steps.transmittance[k];
            Int8 halve;
            const Float8 value = piece_integral8(od_p, od_q, q - p, sigma_t, sigma_t * (p - steps.a[k]), weight, halve);
            halve &= active;
            const Int8 take = active & ~halve;
            partial[0] += take ? steps.light_r[k] * value : zero;
            partial[1] += take ? steps.light_g[k] * value : zero;
            partial[2] += take ? steps.light_b[k] * value : zero;
            if ((i + 1) % kPiecesInFloat == 0 || i + 1 == pieces.count)
                for (int c = 0; c < 3; ++c) {
                    const Float8 v = partial[c];
                    total[c][0] += __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1, 2, 3), Double4);
                    total[c][1] += __builtin_convertvector(__builtin_shufflevector(v, v, 4, 5, 6, 7), Double4);
                    partial[c] = zero;
                }
            taken -= take;
            halved -= halve;
            if (packet::any(halve))
                for (int l = 0; l < int(kTile); ++l)
                    if (halve[l]) {
                        State& st = row_rays.states[l];
                        st.transmittance = weight[l];
                        add_sun_job(st, row_rays.lanes[l], p[l], q[l], steps.a[k][l], sigma_t[l],
                                    Float4{0.0f, steps.light_r[k][l], steps.light_g[k][l], steps.light_b[k][l]});
                    }
        }
        for (int l = 0; l < int(kTile); ++l)
            if (lit_lanes[l]) {
                dvec3& out = sums[row * int(kTile) + l];
                out.x += total[0][l / 4][l % 4];
                out.y += total[1][l / 4][l % 4];
                out.z += total[2][l / 4][l % 4];
            }
        for (int l = 0; l < int(kTile); ++l) {
            counts.lane_sun_pieces += std::uint64_t(taken[l]);
            counts.lane_sun_pieces_halved += std::uint64_t(halved[l]);
        }
    }

    // The ray's box shadows, found at its first lit segment (most rays meet no media).
    void ready_box_shadows(State& st, const Ray& ray) const {
        if (st.shadows_ready) return;
        box_shadows(ray.d, ray.t_opaque, *ray.shadow_scratch, ray.sun_jobs->shadow_mask);
        st.shadows = ray.shadow_scratch->data();
        st.shadow_count = ray.shadow_scratch->size() / 2;
        st.shadows_ready = true;
    }

    // The accurate technique's sun light over the segment [a, b]: light * integral over [a, b] of
    // exp(-sigma_t (t - a)) T_sun(eye + t d) dt, where light = {0, T(a) sigma_s L_sun P(theta)}. T_sun is
    // 0 inside the ray's box shadows (exact intervals) and exp(-optical depth) elsewhere, the depth read
    // from the map at the ends of pieces no longer than kSunPieceCells (halved where it changes fast,
    // sun_jobs::refine_pieces) and linear between them, where the integral has a closed form. The lit pieces go to the
    // tile's jobs (SunJobs), whose integrals resolve_sun_jobs takes after the tile's rays.
    void add_sun_pieces(State& st, const Ray& ray, float a, float b, float sigma_t, const Float4& light) const {
        const float cells = kSunPieceCells * sun_map_.cell(), thin_max = kSunPieceThinWiden * cells;
        ready_box_shadows(st, ray);
        // Most segments (a few cells long, with no box shadow left ahead on their ray) are one piece:
        // the loop below would make the same one. The longest piece is the lanes' (lit_steps_light),
        // its division taken only for a segment longer than kSunPieceCells (on vdb-cloud 4% of them).
        const bool no_shadow = st.shadow_next >= st.shadow_count;
        if (no_shadow && a + cells >= b) {
            if (a < b) add_sun_job(st, ray, a, b, a, sigma_t, light);
            return;
        }
        const float max_piece =
            std::max(std::max(std::min(kSunPieceThinDepth / sigma_t, thin_max), cells), (b - a) / kSunMaxPieces);
        if (no_shadow && a + max_piece >= b) {
            add_sun_job(st, ray, a, b, a, sigma_t, light);
            return;
        }
        float p = a;
        while (p < b) {
            while (st.shadow_next < st.shadow_count && st.shadows[2 * st.shadow_next + 1] <= p) ++st.shadow_next;
            const bool shadowed = st.shadow_next < st.shadow_count && st.shadows[2 * st.shadow_next] <= p;
            float q = std::min(b, p + max_piece);
            if (st.shadow_next < st.shadow_count)
                q = std::min(q, shadowed ? st.shadows[2 * st.shadow_next + 1] : st.shadows[2 * st.shadow_next]);
            if (!(q > p)) q = b;  // a piece shorter than float's step: end the segment (adds nothing)
            if (!shadowed) add_sun_job(st, ray, p, q, a, sigma_t, light);
            p = q;
        }
    }

    // The lit piece [p, q] of the segment that began at a, with T(a) st.transmittance, as one of the
    // tile's jobs (SunJobs::add).
    void add_sun_job(State& st, const Ray& ray, float p, float q, float a, float sigma_t, const Float4& light) const {
        ray.sun_jobs->add(ray.map, ray.ray_id, ray.pixel, st.sun_end, p, q, a, sigma_t, st.transmittance, light);
    }

public:
    // The integrals of the tile's jobs, into its pixels' sums (sun_jobs::resolve).
    template <class Gather>
    void resolve_sun_jobs(SunJobs& jobs, dvec3* pixel_sums, const Gather& gather) const {
        sun_jobs::resolve(sun_map_, jobs, pixel_sums, gather);
    }

private:
    // The segment up to the event, then the event; false once transmittance fell below the threshold.
    template <bool kPlain>
    bool integrate(State& st, const Ray& ray, std::uint64_t key) const {
        const float t = key_distance(key);
        const float len = t - st.t_prev;
        if (len > 0.0f && st.inside > 0) {  // outside every medium a segment adds nothing
            const float x = st.sigma_t() * len;
            float segment_transmittance, w;
            segment_light(x, len, segment_transmittance, w);
            const float tw = st.transmittance * w;
            if (kPlain) {
                st.radiance += st.sigma * ray.source * tw;
            } else if (accurate_shadows_) {
                add_sun_pieces(st, ray, st.t_prev, t, st.sigma_t(), st.sigma * ray.sun_phase * st.transmittance);
                st.radiance += (st.sigma * ray.ambient + st.sigma_e) * tw;
            } else {
                // sigma_s L_s less the sun light the per-sphere shadows take away, plus emission.
                st.radiance += (st.sigma * ray.source - (st.sigma - st.sigma_sun) * ray.sun_phase + st.sigma_e) * tw;
            }
            st.transmittance *= segment_transmittance;
            if (st.transmittance < min_transmittance_) return false;
        }
        st.t_prev = t;
        // Enter or leave the event's medium, without a branch (entries and exits alternate unpredictably):
        // each sum steps by plus or minus the medium's values as a compensated sum (compensated_step),
        // exact to float's rounding of the result however dense the medium left behind; leaving clamps
        // at 0, as the reference does, and back in free space the sums become exactly 0. Branches here
        // mispredicted on one event in four (cachegrind): the masks are arithmetic.
        const std::uint32_t k = std::uint32_t(key) >> 1;
        const int exit = int(key & 1u);
        const float sign = 1.0f - 2.0f * float(exit);  // -1 on an exit, +1 on an entry
        st.inside += 1 - 2 * exit;
        const Int4 exit_mask = Int4{} - exit;                  // all ones on an exit
        const Int4 free_mask = Int4{} - int(st.inside == 0);  // all ones back in free space
        const auto step = [sign, exit_mask, free_mask](Float4& sum, Float4& error, Float4 d) {
            compensated_step(sum, error, sign * d, exit_mask, free_mask);
            return sum + error;
        };
        st.sigma = step(st.sigma_sum, st.sigma_error, extinction_scatter_[k]);
        if (!kPlain) {
            // Only what the light reads: the accurate technique never reads sigma_sun, and where no
            // sphere emits sigma_e stays 0 (branches the predictor always gets right). The same images
            // bit for bit; vdb-cloud's frame, whose one-ray walk steps every event here, 0.96-1.00x.
            const LitMedium& m = lit_media_[k];
            if (!accurate_shadows_) st.sigma_sun = step(st.sun_sum, st.sun_error, m.sun_scatter);
            if (emits_) st.sigma_e = step(st.emission_sum, st.emission_error, m.emission);
        }
        return true;
    }

    std::optional<SunLight> own_sun_;  // where the caller gave none
    const SunLight& sun_;
    FloatSunDepth float_depth_;  // T_sun's depth at a lit box (a scene with none: empty)
    OpaqueSurfaces opaque_;  // after sun_ and float_depth_, which it reads
    SunDepthMap& sun_map_;   // the accurate technique's optical depth toward the sun
    std::vector<BoxShadowVolume> shadow_volumes_;  // the accurate technique's box shadows, those that reach the media
    std::vector<PixelRect> shadow_rects_;          // and the pixels whose rays may meet them there
    std::vector<PixelHull> shadow_hulls_;          // (a tighter bound than the rectangle where it exists)
    std::vector<PixelRect> box_rects_;             // per box, the pixels whose rays may meet it (empty: none)
    dvec3 eye_;
    float min_transmittance_;
    bool accurate_shadows_;
    bool plain_ = true;
    bool emits_ = false;  // whether any sphere emits
    // Per sphere, by position (memory_order):
    std::vector<Float4> extinction_scatter_;  // {tau, tau * albedo}
    std::vector<LitMedium> lit_media_;        // the rest its events add and remove
    std::vector<TileSphere> geometry_;        // what list_tile copies (bound_bits 0)
    dvec3 sun_unit_{0.0};
    dvec3 ambient_{0.0};
    dvec3 lighting_sun_{0.0};
};

}  // namespace

namespace {

// The spheres' indices ordered by bound, ties by index: sorted as (bound, index) pairs, by value (an
// index sort read the bounds at random), in a chunk per worker, then merged pairwise.
std::vector<std::uint32_t> near_to_far(const std::vector<double>& bound, int threads) {
    using Key = std::pair<double, std::uint32_t>;
    const std::size_t n = bound.size();
    std::vector<Key> keys(n);
    for (std::size_t k = 0; k < n; ++k) keys[k] = {bound[k], std::uint32_t(k)};
    const std::size_t chunks = std::size_t(worker_count(threads, n / 65536 + 1));
    const auto edge = [&](std::size_t c) { return keys.begin() + std::ptrdiff_t(std::min(n, c * ((n + chunks - 1) / chunks))); };
    parallel_for(chunks, threads, [&](std::size_t c, int) { std::sort(edge(c), edge(c + 1)); });
    for (std::size_t width = 1; width < chunks; width *= 2)
        parallel_for((chunks + 2 * width - 1) / (2 * width), threads, [&](std::size_t m, int) {
            const std::size_t lo = 2 * width * m;
            if (lo + width < chunks) std::inplace_merge(edge(lo), edge(lo + width), edge(std::min(chunks, lo + 2 * width)));
        });
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = keys[k].second;
    return order;
}

// Where each sphere's data lies in the tracer's memory (its position).
// By the tile its rectangle's centre lies in, the tiles in Z order (bits of the tile's column and row
// interleaved, so that neighbouring tiles are near in the order both ways), and near to far within a
// tile (spheres that cover no pixel last). A tile lists the spheres over it, whose centres lie in it
// or its neighbours, near to far, so its lists and its rays' events read a few runs of memory, each
// mostly forward; in scene order (a simulator's: birth order; a smoke cloud's: random) they read all
// over it. bench scale's smoke clouds at 640x360, two threads, best of 5, in turn with scene order
// (2026-12-07, AMD EPYC): 0.80-0.85x the frame at 1,000,000 spheres (64 MB of the tracer's sphere
// data), 0.94-0.97x at 100,000, 0.97-0.99x at 10,000, the same within the noise at 1,000 and on the
// presets; near to far within a tile rather than in scene order, 0.95-0.98x again at 1,000,000 (one
// thread).
// A counting sort: two passes over the rectangles (the spheres taken near to far, `near_to_far`), over
// at most 4^11 Z-order codes (past 2,048 tiles a side, groups of tiles share a code).
struct MemoryOrder {
    std::vector<std::uint32_t> sphere_at;    // by position, the scene index
    std::vector<std::uint32_t> position_of;  // by scene index, the position
    std::vector<std::uint32_t> near_to_far;  // the positions, near to far (the given order)
};
MemoryOrder memory_order(const std::vector<PixelRect>& rects, const std::vector<std::uint32_t>& near_to_far, int width,
                         int height, int threads) {
    int shift = 0;  // tiles per code: 2^shift a side
    while (((width - 1) / int(kTile) >> shift) >= 2048 || ((height - 1) / int(kTile) >> shift) >= 2048) ++shift;
    const auto spread = [](std::uint32_t v) {  // the bits of v < 2^11 at the even places
        v = (v | (v << 8)) & 0x00ff00ffu;
        v = (v | (v << 4)) & 0x0f0f0f0fu;
        v = (v | (v << 2)) & 0x33333333u;
        return (v | (v << 1)) & 0x55555555u;
    };
    const std::uint32_t last_x = std::uint32_t((width - 1) / int(kTile) >> shift);
    const std::uint32_t last_y = std::uint32_t((height - 1) / int(kTile) >> shift);
    const std::size_t codes = std::size_t(spread(last_x) | (spread(last_y) << 1)) + 1;
    const auto code_of = [&](const PixelRect& r) {
        if (r.x1 <= r.x0 || r.y1 <= r.y0) return codes;  // no pixel
        const int x = std::clamp(r.x0 + (r.x1 - r.x0) / 2, 0, width - 1) / int(kTile) >> shift;
        const int y = std::clamp(r.y0 + (r.y1 - r.y0) / 2, 0, height - 1) / int(kTile) >> shift;
        return std::size_t(spread(std::uint32_t(x)) | (spread(std::uint32_t(y)) << 1));
    };
    // Each sphere's code, in scene order over the threads; then the counts; then the spheres placed near
    // to far, reading the codes (4 bytes a sphere). With the rectangles (16 bytes) read at random there
    // and no codes kept, this took over five times as long at 1,000,000 spheres (perf: 1,258 against
    // 235 samples), all of it serial: about a seventh of the frame on two threads.
    const std::size_t n = rects.size();
    std::vector<std::uint32_t> code(n);
    constexpr std::size_t kChunk = 16384;
    parallel_for((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk, int) {
        for (std::size_t k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k)
            code[k] = std::uint32_t(code_of(rects[k]));
    });
    std::vector<std::uint32_t> next(codes + 2, 0);  // each code's count, then its next position
    for (const std::uint32_t c : code) ++next[c + 1];
    for (std::size_t c = 1; c < next.size(); ++c) next[c] += next[c - 1];
    MemoryOrder order;
    order.sphere_at.resize(n);
    order.position_of.resize(n);
    order.near_to_far.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t k = near_to_far[i], p = next[code[k]]++;
        order.sphere_at[p] = k;
        order.position_of[k] = p;
        order.near_to_far[i] = p;
    }
    return order;
}

// values[sphere_at[p]] at each position p.
template <class T>
std::vector<T> by_position(const std::vector<T>& values, const std::vector<std::uint32_t>& sphere_at, int threads) {
    std::vector<T> out(values.size());
    constexpr std::size_t kChunk = 16384;
    parallel_for((values.size() + kChunk - 1) / kChunk, threads, [&](std::size_t chunk, int) {
        for (std::size_t p = chunk * kChunk; p < std::min(values.size(), (chunk + 1) * kChunk); ++p)
            out[p] = values[sphere_at[p]];
    });
    return out;
}

// What every tile of a frame reads.
struct FrameTiles {
    const FastTracer& tracer;
    const TileBins& bins;
    const std::vector<PixelRect>& rects;
    const CameraRays& rays;
    const std::vector<double>& ndc_x;  // per column (column_ndc)
    int width, height, supersample;
    bool plain;
    bool packets;  // the packet walk where a tile allows it (FastTraceOptions::packets)
};

// A worker's memory for the tiles it traces. A cache line or more each: the workers write their runs'
// heads at every event, and where one worker's scratch ended on the line where the next one's began,
// the line went back and forth between the cores (2 threads on the layers scene at 2 layers, 800x600:
// 16-37 ms a frame, erratically, against 15-16 ms aligned, in the machine's slow state; one thread 38 ms).
struct alignas(64) TileScratch {
    TileLists lists;
    TileRays rays;  // the tile's pixel rays
    packet::Spheres packet;
    packet::OrderedSpheres ordered;
    packet::OrderedEvents ordered_events;
    packet::LitSteps lit_steps;  // a packet row's lit segments (the accurate technique)
    FastTraceCounts counts;  // this worker's tiles by walk (FastTraceOptions::counts)
    FastTracer::RayScratch ray;
    SunJobs sun_jobs;
};

// Each column's ndc_x as CameraRays::direction computes it for the pixel centre, 2 (i + 0.5) / width - 1,
// for every column of the tiles (past the image's width too): a quotient a frame, not one a pixel.
std::vector<double> column_ndc(const CameraRays& c, std::size_t columns) {
    std::vector<double> ndc(columns);
    for (std::size_t i = 0; i < columns; ++i) ndc[i] = 2.0 * (double(i) + 0.5) / c.width - 1.0;
    return ndc;
}

// The tile's pixel-centre rays (CameraRays::pixel_direction, the same operations in the same order),
// four pixels at a time. One at a time they were a tenth of a frame where the tile's spheres are few
// (2 layers, 800x600). `ndc_x_of_column`: column_ndc's.
[[gnu::always_inline]] inline void pixel_directions(const CameraRays& c, const double* ndc_x_of_column, int i0, int j0,
                                                    TileRays& out) {
    for (int y = 0; y < int(kTile); ++y) {
        const double ndc_y = 2.0 * (double(j0 + y) + 0.5) / c.height - 1.0;
        for (int x0 = 0; x0 < int(kTile); x0 += 4) {
            Double4 ndc_x;
            std::memcpy(&ndc_x, ndc_x_of_column + i0 + x0, sizeof ndc_x);
            // forward + ndc_x * right - ndc_y * up, then normalize: v * (1 / sqrt(dot(v, v))).
            const Double4 vx = (c.forward.x + ndc_x * c.right.x) - ndc_y * c.up.x;
            const Double4 vy = (c.forward.y + ndc_x * c.right.y) - ndc_y * c.up.y;
            const Double4 vz = (c.forward.z + ndc_x * c.right.z) - ndc_y * c.up.z;
            const Double4 xx = vx * vx, yy = vy * vy, zz = vz * vz;
            const Double4 inverse = 1.0 / sqrt4((xx + yy) + zz);
            const Double4 dx = vx * inverse, dy = vy * inverse, dz = vz * inverse;
            const int p = y * int(kTile) + x0;
            std::memcpy(out.x + p, &dx, sizeof dx);
            std::memcpy(out.y + p, &dy, sizeof dy);
            std::memcpy(out.z + p, &dz, sizeof dz);
            const Float4 fx = __builtin_convertvector(dx, Float4), fy = __builtin_convertvector(dy, Float4),
                         fz = __builtin_convertvector(dz, Float4);
            std::memcpy(out.fx + p, &fx, sizeof fx);
            std::memcpy(out.fy + p, &fy, sizeof fy);
            std::memcpy(out.fz + p, &fz, sizeof fz);
        }
    }
}

// Whether tile t takes the ordered walk (render/ordered_walk.h): one ray a pixel, more spheres than the
// packet walk takes and at most packet::kMaxOrderedSpheres, whose pixel rectangles cover on average
// at least kOrderedCover of the tile. Where the spheres are small against the tile (plume's puffs,
// pop), most lanes miss most of them, and their orders differ from pixel to pixel.
// At 0.5 ground-fog's unshadowed frame took 0.89x what it takes at 0.8, but explosion's, campfire's
// and crossing's 1.05-1.07x the one-ray walk's (their mid-sized puffs); at 0.8 those stay within 2%.
constexpr double kOrderedCover = 0.8;

bool takes_ordered_walk(const FrameTiles& f, std::size_t t) {
    const std::size_t count = f.bins.first[t + 1] - f.bins.first[t];
    if (!f.packets || f.supersample != 1 || count <= std::size_t(packet::kMaxSpheres) ||
        count > std::size_t(packet::kMaxOrderedSpheres))
        return false;
    const std::uint32_t* entries = f.bins.entries.data() + 2 * std::size_t(f.bins.first[t]);
    const int i0 = int(t % f.bins.tiles_x * kTile), j0 = int(t / f.bins.tiles_x * kTile);
    const int i1 = i0 + int(kTile), j1 = j0 + int(kTile);
    long covered = 0;
    for (std::size_t n = 0; n < count; ++n) {
        const PixelRect& r = f.rects[entries[2 * n]];
        covered += long(std::max(0, std::min(r.x1, i1) - std::max(r.x0, i0))) * std::max(0, std::min(r.y1, j1) - std::max(r.y0, j0));
    }
    return double(covered) >= kOrderedCover * double(kTile * kTile) * double(count);
}

// Whether trace_tile is being compiled for AVX2, told by the gather it was handed (trace_tile_avx2's).
template <class Gather>
constexpr bool kCompiledForAvx2 = false;
#if defined(__x86_64__) && defined(__GNUC__)
template <>
constexpr bool kCompiledForAvx2<simd::GatherAvx2> = true;
#endif

// Whether the packet and ordered walks (eight rays in SIMD lanes) are taken: in the code compiled for
// AVX2 only. In the portable code eight lanes are two SSE2 registers, a walk's sixteen event slots of
// them spill to the stack and a select takes three instructions, so there the lanes were slower than
// walking each ray alone: one thread, 640x360, layers 188 against 76 ms a frame, fog-bank 315 against
// 132 (594 against 391 shadowed), low-sun 150 against 62, ground-fog 196 against 92, plume 60 against
// 51; only explosion's went the other way, 47 against 53 (docs/performance.md, "On an AMD EPYC").
template <class Gather>
constexpr bool kWalksInLanes = kCompiledForAvx2<Gather>;

// Tile t: its pixel lists, then its pixels, each handed to store(i, j, value); `gather` reads the sun
// map's vertices (render/simd8.h).
template <bool kOrdered, class Store, class Gather>
inline void trace_tile(const FrameTiles& f, std::size_t t, TileScratch& w, const Store& store, const Gather& gather) {
    constexpr bool kWide = kCompiledForAvx2<Gather>;
    const int k = f.supersample;
    const int i0 = int(t % f.bins.tiles_x * kTile), j0 = int(t / f.bins.tiles_x * kTile);
    // The tile's pixel rays, and in float as the tracer takes them (one ray a pixel: no supersampling).
    TileRays& tile_rays = w.rays;
    if (k == 1) pixel_directions(f.rays, f.ndc_x.data(), i0, j0, tile_rays);
    const std::uint32_t* entries = f.bins.entries.data() + 2 * std::size_t(f.bins.first[t]);
    const std::size_t entry_count = f.bins.first[t + 1] - f.bins.first[t];
    // A tile of few spheres, one ray a pixel: eight rays at once, a row at a time (render/packet_walk.h),
    // in the code compiled for AVX2 (kWalksInLanes).
    const bool packets = kWalksInLanes<Gather> && !kOrdered && f.packets && k == 1 &&
                         entry_count <= std::size_t(packet::kMaxSpheres);
    // More spheres, up to a few dozen, that cover the tile (takes_ordered_walk): eight rays at once in an
    // order they share (render/ordered_walk.h), a ray whose order differs by the one-ray walk, whose
    // lists are then made. Compiled apart (kOrdered), so that its code does not enlarge the others'.
    const bool ordered = kOrdered;
    if (packets)
        f.tracer.packet_spheres(entries, entry_count, f.rects, i0, j0, w.packet);
    else if (ordered)
        f.tracer.ordered_spheres(entries, entry_count, f.rects, i0, j0, w.ordered);
    else
        f.tracer.list_tile(entries, entry_count, f.rects, i0, j0, k == 1 ? &tile_rays : nullptr, w.lists);
    // Each pixel's sum over its rays; with accurate shadows the sun's light joins it after all the
    // tile's rays (FastTracer::resolve_sun_jobs).
    dvec3 sums[kTile * kTile];
    w.sun_jobs.clear();
    const int i1 = std::min(i0 + int(kTile), f.width), j1 = std::min(j0 + int(kTile), f.height);
    w.sun_jobs.shadow_mask = f.tracer.tile_shadow_mask(i0, j0, i1, j1);
    const std::uint64_t boxes = f.tracer.tile_box_mask(i0, j0, i1, j1);
    // The tile pixels the one-ray walk takes: all of them but where a packet walk does, and there the
    // rays whose order the ordered walk could not put right (one copy of that walk, inlined once).
    std::uint64_t one_ray = 0;
    if (ordered) {
        const unsigned columns = (1u << (i1 - i0)) - 1u;  // lanes past the image's edge are not stored
        const auto rows = [&]<packet::Light kLight>() {
            for (int j = j0; j < j1; ++j)
                one_ray |= std::uint64_t(f.tracer.template radiance_ordered_row<kLight>(
                                             w.ordered, tile_rays, j - j0, boxes, w.ray, w.sun_jobs, w.ordered_events,
                                             w.lit_steps, gather, w.counts, sums) &
                                         columns)
                           << ((j - j0) * int(kTile));
        };
        switch (f.tracer.packet_light()) {
            case packet::Light::kPlain: rows.template operator()<packet::Light::kPlain>(); break;
            case packet::Light::kPerSphere: rows.template operator()<packet::Light::kPerSphere>(); break;
            case packet::Light::kAccurate: rows.template operator()<packet::Light::kAccurate>(); break;
        }
        if (one_ray != 0) f.tracer.list_tile(entries, entry_count, f.rects, i0, j0, &tile_rays, w.lists);
        ++w.counts.ordered_tiles;
        w.counts.ordered_rays_alone += std::uint64_t(std::popcount(one_ray));
    } else if (packets) {
        ++w.counts.packet_tiles;
        const auto rows = [&]<packet::Light kLight>() {
            for (int j = j0; j < j1; ++j)
                f.tracer.template radiance_row<kLight>(w.packet, tile_rays, j - j0, boxes, w.ray, w.sun_jobs,
                                                       w.lit_steps, gather, w.counts, sums);
        };
        switch (f.tracer.packet_light()) {
            case packet::Light::kPlain: rows.template operator()<packet::Light::kPlain>(); break;
            case packet::Light::kPerSphere: rows.template operator()<packet::Light::kPerSphere>(); break;
            case packet::Light::kAccurate: rows.template operator()<packet::Light::kAccurate>(); break;
        }
    } else {
        ++w.counts.one_ray_tiles;
        for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i) one_ray |= std::uint64_t(1) << ((j - j0) * int(kTile) + (i - i0));
    }
    // The one-ray walk's opaque surfaces, a row of eight rays at a time (one ray a pixel only).
    OpaqueSurfaces::Hit opaque_hits[kTile * kTile];
    if (k == 1)
        for (int row = 0; row < int(kTile); ++row)
            if ((one_ray >> (row * int(kTile))) & 0xffu)
                f.tracer.row_opaque_hits(tile_rays, row, boxes, opaque_hits + row * int(kTile));
    for (; one_ray != 0; one_ray &= one_ray - 1) {
        const std::uint32_t p = std::uint32_t(std::countr_zero(one_ray));
        const int i = i0 + int(p % kTile), j = j0 + int(p / kTile);
        dvec3 sum(0.0);
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a) {
                const dvec3 d = k == 1 ? tile_rays.direction(int(p)) : f.rays.direction(i + (a + 0.5) / k, j + (b + 0.5) / k);
                const OpaqueSurfaces::Hit* known = k == 1 ? opaque_hits + p : nullptr;
                const std::uint32_t* items = w.lists.items.data() + w.lists.first[p];
                const std::size_t count = w.lists.count[p];
                sum += f.plain ? f.tracer.radiance<true, kWide>(d, w.lists.spheres.data(), items, count, w.ray,
                                                                w.sun_jobs, p, boxes, known)
                               : f.tracer.radiance<false, kWide>(d, w.lists.spheres.data(), items, count, w.ray,
                                                                 w.sun_jobs, p, boxes, known);
            }
        sums[p] = sum;
    }
    w.counts.job_sun_pieces += w.sun_jobs.count;
    f.tracer.resolve_sun_jobs(w.sun_jobs, sums, gather);
    for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i)
            store(i, j, sums[(j - j0) * int(kTile) + (i - i0)] / double(k * k));
}

// trace_tile compiled twice, everything it calls that can be inlined inlined into it (flatten): for
// any x86-64, and for one with AVX2 and FMA, where the same code ran 5-18% faster a frame when this
// was built and 1.5-3.4x faster once its walks ran in eight lanes (docs/performance.md). Nothing but
// what is inlined here takes the second target, so no function the rest of the program calls (a
// template that another file also instantiates, say) is ever compiled for it.
template <bool kOrdered, class Store>
[[gnu::flatten]] void trace_tile_portable(const FrameTiles& f, std::size_t t, TileScratch& w, const Store& store) {
    trace_tile<kOrdered>(f, t, w, store, simd::GatherByLanes{});
}
#if defined(__x86_64__) && defined(__GNUC__)
template <bool kOrdered, class Store>
[[gnu::flatten, gnu::target("avx2,fma")]] void trace_tile_avx2(const FrameTiles& f, std::size_t t, TileScratch& w,
                                                                 const Store& store) {
    trace_tile<kOrdered>(f, t, w, store, simd::GatherAvx2{});
}
#endif

// The frame, each pixel handed to store(i, j, value) once (from the worker that traced it).
template <class Store>
void trace_frame(const Scene& scene, const FastTraceOptions& options, const Store& store) {
    if (!scene.volumes.empty())
        throw std::logic_error("fast tracer: the scene's [[vdb]] volumes were not converted to spheres "
                               "(sim/vdb/volume_loader.h convert_scene_volumes)");
    const int width = scene.camera.width, height = scene.camera.height;
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("fast tracer: camera of " + std::to_string(width) + "x" + std::to_string(height) +
                                    " pixels");
    const int k = scene.camera.supersample;
    if (k < 1 || k > kMaxSupersample)
        throw std::invalid_argument("fast tracer: supersample " + std::to_string(k) + " (must be 1 to " +
                                    std::to_string(kMaxSupersample) + ")");

    // The frame's serial part, spread over the threads where it can be: at 1,000,000 spheres it took
    // 570 ms of a 1,970 ms frame (the rectangles twice, 165 ms, and the sort by bound, 138 ms).
    // Each sphere's pixel rectangle, for the binning and for the tiles' pixel lists, and its nearest
    // bound; from here on by position (memory_order).
    const std::vector<PixelRect> scene_rects = sphere_pixel_rects(scene, width, height, options.threads);
    std::vector<double> scene_bound;
    nearest_event_bounds(scene, scene_bound, options.threads);
    const std::vector<std::uint32_t> scene_order = near_to_far(scene_bound, options.threads);
    const MemoryOrder memory = memory_order(scene_rects, scene_order, width, height, options.threads);
    const std::vector<PixelRect> rects = by_position(scene_rects, memory.sphere_at, options.threads);
    const std::vector<double> bound = by_position(scene_bound, memory.sphere_at, options.threads);
    SunDepthMap own_map;
    const FastTracer tracer(scene, memory.position_of, options.threads,
                            options.scratch ? options.scratch->sun_map : own_map, options.sun,
                            options.instructions == TraceInstructions::Best ? MapInstructions::Best
                                                                             : MapInstructions::Portable);
    TileBins bins;
    bin_spheres(rects, width, height, kTile, memory.near_to_far, bound, bins, options.threads);

    const CameraRays rays = make_camera_rays(scene.camera);
    const std::vector<double> ndc_x = column_ndc(rays, std::size_t(bins.tiles_x) * kTile);
    const FrameTiles frame{tracer, bins, rects, rays, ndc_x, width, height, k, tracer.plain(), options.packets};
    const std::size_t tiles = bins.tile_count();
    std::vector<TileScratch> scratch(std::size_t(worker_count(options.threads, tiles)));
    const bool avx2 = options.instructions == TraceInstructions::Best && simd::cpu_has_avx2_fma();
    // The packet and ordered walks only in the code compiled for AVX2 (kWalksInLanes): the portable code
    // walks every ray alone.
    parallel_for(tiles, options.threads, [&](std::size_t t, int worker) {
        TileScratch& w = scratch[std::size_t(worker)];
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx2)
            return takes_ordered_walk(frame, t) ? trace_tile_avx2<true>(frame, t, w, store)
                                                : trace_tile_avx2<false>(frame, t, w, store);
#endif
        trace_tile_portable<false>(frame, t, w, store);
    });
    if (options.counts) {
        *options.counts = FastTraceCounts{};
        for (const TileScratch& w : scratch) {
            options.counts->packet_tiles += w.counts.packet_tiles;
            options.counts->ordered_tiles += w.counts.ordered_tiles;
            options.counts->one_ray_tiles += w.counts.one_ray_tiles;
            options.counts->ordered_rays_alone += w.counts.ordered_rays_alone;
            options.counts->lane_sun_pieces += w.counts.lane_sun_pieces;
            options.counts->job_sun_pieces += w.counts.job_sun_pieces;
            options.counts->lane_sun_pieces_halved += w.counts.lane_sun_pieces_halved;
        }
    }
}

}  // namespace

const char* fast_trace_instructions(const FastTraceOptions& options) {
    return options.instructions == TraceInstructions::Best && simd::cpu_has_avx2_fma() ? "AVX2+FMA" : "portable";
}

Image render_fast_trace(const Scene& scene, const FastTraceOptions& options) {
    Image image(scene.camera.width > 0 ? scene.camera.width : 0, scene.camera.height > 0 ? scene.camera.height : 0);
    trace_frame(scene, options, [&image](int i, int j, const dvec3& v) {
        float* p = image.pixel(i, j);
        p[0] = float(v.x);
        p[1] = float(v.y);
        p[2] = float(v.z);
    });
    return image;
}

void render_fast_trace_rgba(const Scene& scene, const FastTraceOptions& options, float* rgba) {
    const std::size_t width = std::size_t(std::max(scene.camera.width, 0));
    trace_frame(scene, options, [rgba, width](int i, int j, const dvec3& v) {
        float* p = rgba + 4 * (std::size_t(j) * width + std::size_t(i));
        p[0] = float(v.x);
        p[1] = float(v.y);
        p[2] = float(v.z);
        p[3] = 1.0f;
    });
}

}  // namespace brume
