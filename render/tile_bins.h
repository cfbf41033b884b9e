// Screen tiles and the spheres that may be seen in each, for the `tiles` resolve
// (render/methods/tiles.h, shaders/tiles_resolve.comp): each sphere is listed in every tile its
// screen rectangle meets, in the order it is given (near to far by its nearest bound), so each
// tile's list comes sorted. CPU only, so that the binning is tested without a device.
#pragma once

#include "sim/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace brume {

// One listed sphere's tile rectangle [x0, x1) x [y0, y1) (x0 == x1: none) and the bits of its float
// bound, in the order the spheres are binned: the binning's scratch.
struct BinnedRect {
    std::uint16_t x0, y0, x1, y1;
    std::uint32_t bound_bits;
};

struct TileBins {
    std::uint32_t tile_size = 0;
    std::uint32_t tiles_x = 0, tiles_y = 0;
    // Tile t (row-major) lists entries first[t] .. first[t + 1]; first has tiles + 1 elements.
    std::vector<std::uint32_t> first;
    // Pairs (sphere, bits of float(bound)), tile after tile, then one sentinel pair whose bound (3e38) is
    // past every distance (the shader may read the entry at a tile's end).
    std::vector<std::uint32_t> entries;
    std::uint32_t longest = 0;  // the most spheres listed in one tile
    // The binning's scratch, kept so that a frame reuses the last one's memory (a million spheres: 12 MB
    // that would otherwise be allocated and zeroed every frame).
    std::vector<BinnedRect> scratch;

    std::uint64_t entry_count() const { return first.empty() ? 0 : first.back(); }
    std::uint32_t tile_count() const { return tiles_x * tiles_y; }
};

// The pixel rectangle [x0, x1) x [y0, y1) of an image of width x height pixels that holds every pixel
// centre whose ray may meet the sphere, padded by a pixel for float rounding; false when it holds
// none. Exact up to that pad: the bounds come from the planes through the eye tangent to the sphere.
// A sphere around or beside the eye's plane covers the whole image.
struct PixelRect {
    int x0, y0, x1, y1;
};
bool sphere_pixel_rect(const Sphere& sphere, const Camera& camera, int width, int height, PixelRect& rect);
// The pixels (centres and, as sphere_pixel_rect's, a pixel more each way) whose rays may meet the convex
// hull of points[0, count): their projection's rectangle, or the whole image where a point is not in
// front of the eye. False where no pixel's.
bool hull_pixel_rect(const glm::dvec3* points, int count, const Camera& camera, int width, int height,
                     PixelRect& rect);
// points[0, count) in pixel coordinates (pixel i spans [i, i + 1], y down; hull_pixel_rect's projection)
// into out; false, out unwritten, where a point is not in front of the eye (its projection unbounded).
bool project_to_pixels(const glm::dvec3* points, int count, const Camera& camera, int width, int height,
                       glm::dvec2* out);
// Every sphere's rectangle, in scene order, over `threads` (0: every usable CPU); an empty one
// ({0, 0, 0, 0}) where the sphere has no extinction or covers no pixel.
std::vector<PixelRect> sphere_pixel_rects(const Scene& scene, int width, int height, int threads);

// Bins the spheres `order` names (spheres without extinction are left out) into tiles of
// tile_size pixels over a width x height image; bound[k] is sphere k's nearest bound
// (render/nearest_bounds.h); over `threads` (0: every usable CPU), with the same bins on any
// number.
void bin_spheres(const Scene& scene, int width, int height, std::uint32_t tile_size,
                 const std::vector<std::uint32_t>& order, const std::vector<double>& bound, TileBins& bins,
                 int threads = 0);
// The same from rectangles sphere_pixel_rects made (empty ones are left out).
void bin_spheres(const std::vector<PixelRect>& rects, int width, int height, std::uint32_t tile_size,
                 const std::vector<std::uint32_t>& order, const std::vector<double>& bound, TileBins& bins,
                 int threads = 0);

}  // namespace brume
