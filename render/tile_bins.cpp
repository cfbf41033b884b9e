#include "render/tile_bins.h"

#include "sim/camera_rays.h"
#include "sim/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace brume {

namespace {

// The camera as pixel_rect reads it, made once per frame: unit right and up axes and the reciprocals of
// the rays' half-extents, so that a sphere costs two square roots and two divisions.
struct RectCamera {
    glm::dvec3 eye, forward, right, up;  // right and up of unit length
    double inv_sx, inv_sy;               // 1 / length(rays.right), 1 / length(rays.up)

    explicit RectCamera(const CameraRays& rays)
        : eye(rays.eye), forward(rays.forward), inv_sx(1.0 / glm::length(rays.right)),
          inv_sy(1.0 / glm::length(rays.up)) {
        right = rays.right * inv_sx;
        up = rays.up * inv_sy;
    }
};

// The interval of tangent slopes (lateral / depth) of a sphere seen from the eye, along one axis;
// inv_denom = 1 / (depth^2 - r^2).
void tangent_slopes(double lateral, double depth, double r, double denom, double inv_denom, double& lo, double& hi) {
    const double root = r * std::sqrt(std::max(lateral * lateral + denom, 0.0));
    lo = (lateral * depth - root) * inv_denom;
    hi = (lateral * depth + root) * inv_denom;
}

int clamp_to(double v, int lo, int hi) {
    if (!(v > lo)) return lo;  // NaN too
    if (v > hi) return hi;
    return int(v);
}

// sphere_pixel_rect with the camera made once.
bool pixel_rect(const Sphere& s, const RectCamera& cam, int width, int height, PixelRect& rect) {
    const glm::dvec3 v = s.center - cam.eye;
    const double depth = glm::dot(v, cam.forward);
    if (depth < -s.radius) return false;  // wholly behind the eye: every pixel ray looks forward
    if (depth <= s.radius * 1.001) {
        rect = {0, 0, width, height};
        return true;
    }
    const double denom = depth * depth - s.radius * s.radius;  // > 0: the eye is outside the sphere
    const double inv_denom = 1.0 / denom;
    double x_lo, x_hi, y_lo, y_hi;
    tangent_slopes(glm::dot(v, cam.right), depth, s.radius, denom, inv_denom, x_lo, x_hi);
    tangent_slopes(glm::dot(v, cam.up), depth, s.radius, denom, inv_denom, y_lo, y_hi);
    // Pixel centre i + 0.5 has ndc 2 (i + 0.5) / w - 1 and slope ndc * sx (y: down, -ndc * sy).
    const double px0 = (x_lo * cam.inv_sx + 1.0) * 0.5 * width, px1 = (x_hi * cam.inv_sx + 1.0) * 0.5 * width;
    const double py0 = (1.0 - y_hi * cam.inv_sy) * 0.5 * height, py1 = (1.0 - y_lo * cam.inv_sy) * 0.5 * height;
    // Centres inside [p0, p1] are pixels floor(p0 - 0.5) + 1 .. floor(p1 - 0.5); a pixel more each way
    // (which also covers the rounding of the reciprocals above).
    rect.x0 = clamp_to(std::floor(px0 - 0.5), 0, width);
    rect.x1 = clamp_to(std::floor(px1 - 0.5) + 2.0, 0, width);
    rect.y0 = clamp_to(std::floor(py0 - 0.5), 0, height);
    rect.y1 = clamp_to(std::floor(py1 - 0.5) + 2.0, 0, height);
    return rect.x0 < rect.x1 && rect.y0 < rect.y1;
}

}  // namespace

bool sphere_pixel_rect(const Sphere& s, const Camera& camera, int width, int height, PixelRect& rect) {
    return pixel_rect(s, RectCamera(make_camera_rays(camera)), width, height, rect);
}

bool project_to_pixels(const glm::dvec3* points, int count, const Camera& camera, int width, int height,
                       glm::dvec2* out) {
    const RectCamera cam(make_camera_rays(camera));
    for (int n = 0; n < count; ++n) {
        const glm::dvec3 v = points[n] - cam.eye;
        const double depth = glm::dot(v, cam.forward);
        // At or behind the eye's plane (or NaN) the projection is unbounded.
        if (!(depth > 1e-9 * (glm::length(v) + 1e-300))) return false;
        // Pixel centre i + 0.5 has ndc 2 (i + 0.5) / w - 1 and slope ndc * sx (y: down), as pixel_rect's.
        out[n] = glm::dvec2((glm::dot(v, cam.right) / depth * cam.inv_sx + 1.0) * 0.5 * width,
                            (1.0 - glm::dot(v, cam.up) / depth * cam.inv_sy) * 0.5 * height);
    }
    return true;
}

bool hull_pixel_rect(const glm::dvec3* points, int count, const Camera& camera, int width, int height,
                     PixelRect& rect) {
    if (count <= 0) return false;
    std::vector<glm::dvec2> projected(static_cast<std::size_t>(count));
    if (!project_to_pixels(points, count, camera, width, height, projected.data())) {
        rect = {0, 0, width, height};  // unbounded: every pixel may see it
        return width > 0 && height > 0;
    }
    double px0 = std::numeric_limits<double>::infinity(), px1 = -px0, py0 = px0, py1 = -px0;
    for (const glm::dvec2& q : projected) {
        px0 = std::min(px0, q.x);
        px1 = std::max(px1, q.x);
        py0 = std::min(py0, q.y);
        py1 = std::max(py1, q.y);
    }
    rect.x0 = clamp_to(std::floor(px0 - 0.5), 0, width);
    rect.x1 = clamp_to(std::floor(px1 - 0.5) + 2.0, 0, width);
    rect.y0 = clamp_to(std::floor(py0 - 0.5), 0, height);
    rect.y1 = clamp_to(std::floor(py1 - 0.5) + 2.0, 0, height);
    return rect.x0 < rect.x1 && rect.y0 < rect.y1;
}

std::vector<PixelRect> sphere_pixel_rects(const Scene& scene, int width, int height, int threads) {
    const RectCamera cam(make_camera_rays(scene.camera));
    const std::size_t n = scene.spheres.size();
    std::vector<PixelRect> rects(n);
    constexpr std::size_t kChunk = 4096;  // spheres per work item: a million spheres take 80 ms on one core
    parallel_for((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk, int) {
        for (std::size_t k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k) {
            const Sphere& s = scene.spheres[k];
            if (!(s.extinction > 0.0) || !pixel_rect(s, cam, width, height, rects[k])) rects[k] = PixelRect{0, 0, 0, 0};
        }
    });
    return rects;
}

void bin_spheres(const Scene& scene, int width, int height, std::uint32_t tile_size,
                 const std::vector<std::uint32_t>& order, const std::vector<double>& bound, TileBins& bins,
                 int threads) {
    if (tile_size == 0 || width <= 0 || height <= 0) throw std::invalid_argument("bin_spheres: empty image or tile");
    bin_spheres(sphere_pixel_rects(scene, width, height, threads), width, height, tile_size, order, bound, bins, threads);
}

void bin_spheres(const std::vector<PixelRect>& pixel_rects, int width, int height, std::uint32_t tile_size,
                 const std::vector<std::uint32_t>& order, const std::vector<double>& bound, TileBins& bins,
                 int threads) {
    if (tile_size == 0 || width <= 0 || height <= 0) throw std::invalid_argument("bin_spheres: empty image or tile");
    bins.tile_size = tile_size;
    bins.tiles_x = (std::uint32_t(width) + tile_size - 1) / tile_size;
    bins.tiles_y = (std::uint32_t(height) + tile_size - 1) / tile_size;
    if (bins.tiles_x > 0xffff || bins.tiles_y > 0xffff)
        throw std::invalid_argument("bin_spheres: more than 65,535 tiles across or down");
    const std::uint32_t tiles = bins.tiles_x * bins.tiles_y;
    // A stable counting sort over chunks of `order`, each chunk on a thread: each counts its spheres
    // per tile, the prefix sums (tile after tile, chunk after chunk within a tile) give every chunk
    // its own place in each tile's list, and each fills its places in its own order. So each tile
    // lists its spheres in the given order, as one thread would, and no two threads write one place.
    // A million spheres: 60 ms on one core, most of it cache misses of the counts and the entries.
    const std::size_t n = order.size();
    constexpr std::size_t kMinChunk = 16384;  // below this a chunk's counts cost more than its spheres
    std::size_t chunks = std::max<std::size_t>(1, std::min<std::size_t>(n / kMinChunk, 4 * std::size_t(worker_count(threads, n))));
    chunks = std::min<std::size_t>(chunks, std::max<std::size_t>(1, (std::size_t(1) << 22) / tiles));  // counts: 16 MiB at most
    const std::size_t per_chunk = (n + chunks - 1) / std::max<std::size_t>(chunks, 1);
    std::vector<BinnedRect>& rects = bins.scratch;
    rects.resize(n);
    std::vector<std::uint32_t> place(chunks * tiles, 0);  // counts, then each chunk's next place per tile
    // Pass 1: each sphere's tile rectangle and bound, gathered in the given order (a loop of independent
    // loads, so that many cache misses are in flight at once), then each chunk's count per tile.
    parallel_for(chunks, threads, [&](std::size_t c, int) {
        for (std::size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i) {
            const std::uint32_t k = order[i];
            const PixelRect r = pixel_rects[k];
            const bool seen = r.x0 < r.x1 && r.y0 < r.y1;  // else no extinction, or no pixel
            rects[i] = seen ? BinnedRect{std::uint16_t(std::uint32_t(r.x0) / tile_size),
                                         std::uint16_t(std::uint32_t(r.y0) / tile_size),
                                         std::uint16_t((std::uint32_t(r.x1) + tile_size - 1) / tile_size),
                                         std::uint16_t((std::uint32_t(r.y1) + tile_size - 1) / tile_size),
                                         std::bit_cast<std::uint32_t>(float(bound[k]))}
                            : BinnedRect{0, 0, 0, 0, 0};
        }
        std::uint32_t* count = place.data() + c * tiles;
        for (std::size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i) {
            const BinnedRect& t = rects[i];
            for (std::uint32_t y = t.y0; y < t.y1; ++y)
                for (std::uint32_t x = t.x0; x < t.x1; ++x) ++count[y * bins.tiles_x + x];
        }
    });
    // Prefix sums; entries are addressed by 32-bit offsets on the device.
    bins.first.assign(tiles + 1, 0);
    std::uint64_t total = 0;
    bins.longest = 0;
    for (std::uint32_t t = 0; t < tiles; ++t) {
        bins.first[t] = std::uint32_t(total);
        const std::uint64_t tile_start = total;
        for (std::size_t c = 0; c < chunks; ++c) {
            const std::uint32_t count = place[c * tiles + t];
            place[c * tiles + t] = std::uint32_t(total);
            total += count;
        }
        bins.longest = std::max<std::uint32_t>(bins.longest, std::uint32_t(total - tile_start));
        if (total >= std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("the tile lists need more than 2^32 entries; lower the resolution or the particle count");
    }
    bins.first[tiles] = std::uint32_t(total);
    // Pass 2: each chunk fills its places, in the given order.
    bins.entries.resize(2 * (total + 1));
    parallel_for(chunks, threads, [&](std::size_t c, int) {
        std::uint32_t* next = place.data() + c * tiles;
        for (std::size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i) {
            const BinnedRect& t = rects[i];
            if (t.x0 == t.x1) continue;
            const std::uint32_t sphere = order[i];
            const std::uint32_t bits = t.bound_bits;
            for (std::uint32_t y = t.y0; y < t.y1; ++y)
                for (std::uint32_t x = t.x0; x < t.x1; ++x) {
                    const std::uint32_t at = next[y * bins.tiles_x + x]++;
                    bins.entries[2 * at] = sphere;
                    bins.entries[2 * at + 1] = bits;
                }
        }
    });
    bins.entries[2 * total] = 0;
    // 3e38: past every distance a scene holds, and below the shader's empty slot (NO_T, 3.4e38).
    bins.entries[2 * total + 1] = std::bit_cast<std::uint32_t>(3.0e38f);
}

}  // namespace brume
