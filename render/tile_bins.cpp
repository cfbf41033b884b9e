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

// The interval of tangent slopes (lateral / depth) of a sphere seen from the eye, along one axis.
void tangent_slopes(double lateral, double depth, double r, double& lo, double& hi) {
    const double denom = depth * depth - r * r;
    const double root = r * std::sqrt(std::max(lateral * lateral + denom, 0.0));
    lo = (lateral * depth - root) / denom;
    hi = (lateral * depth + root) / denom;
}

int clamp_to(double v, int lo, int hi) {
    if (!(v > lo)) return lo;  // NaN too
    if (v > hi) return hi;
    return int(v);
}

// sphere_pixel_rect with the camera's rays made once: sx and sy are the lengths of rays.right and
// rays.up.
bool pixel_rect(const Sphere& s, const CameraRays& rays, double sx, double sy, int width, int height, PixelRect& rect) {
    const glm::dvec3 v = s.center - rays.eye;
    const double depth = glm::dot(v, rays.forward);
    if (depth < -s.radius) return false;  // wholly behind the eye: every pixel ray looks forward
    if (depth <= s.radius * 1.001) {
        rect = {0, 0, width, height};
        return true;
    }
    double x_lo, x_hi, y_lo, y_hi;
    tangent_slopes(glm::dot(v, rays.right / sx), depth, s.radius, x_lo, x_hi);
    tangent_slopes(glm::dot(v, rays.up / sy), depth, s.radius, y_lo, y_hi);
    // Pixel centre i + 0.5 has ndc 2 (i + 0.5) / w - 1 and slope ndc * sx (y: down, -ndc * sy).
    const double px0 = (x_lo / sx + 1.0) * 0.5 * width, px1 = (x_hi / sx + 1.0) * 0.5 * width;
    const double py0 = (1.0 - y_hi / sy) * 0.5 * height, py1 = (1.0 - y_lo / sy) * 0.5 * height;
    // Centres inside [p0, p1] are pixels floor(p0 - 0.5) + 1 .. floor(p1 - 0.5); a pixel more each way.
    rect.x0 = clamp_to(std::floor(px0 - 0.5), 0, width);
    rect.x1 = clamp_to(std::floor(px1 - 0.5) + 2.0, 0, width);
    rect.y0 = clamp_to(std::floor(py0 - 0.5), 0, height);
    rect.y1 = clamp_to(std::floor(py1 - 0.5) + 2.0, 0, height);
    return rect.x0 < rect.x1 && rect.y0 < rect.y1;
}

}  // namespace

bool sphere_pixel_rect(const Sphere& s, const Camera& camera, int width, int height, PixelRect& rect) {
    const CameraRays rays = make_camera_rays(camera);
    return pixel_rect(s, rays, glm::length(rays.right), glm::length(rays.up), width, height, rect);
}

std::vector<PixelRect> sphere_pixel_rects(const Scene& scene, int width, int height, int threads) {
    const CameraRays rays = make_camera_rays(scene.camera);
    const double sx = glm::length(rays.right), sy = glm::length(rays.up);
    const std::size_t n = scene.spheres.size();
    std::vector<PixelRect> rects(n);
    constexpr std::size_t kChunk = 4096;  // spheres per work item: a million spheres take 80 ms on one core
    parallel_for((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk, int) {
        for (std::size_t k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k) {
            const Sphere& s = scene.spheres[k];
            if (!(s.extinction > 0.0) || !pixel_rect(s, rays, sx, sy, width, height, rects[k])) rects[k] = PixelRect{0, 0, 0, 0};
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
    struct TileRect {
        std::uint32_t x0, y0, x1, y1;  // tiles [x0, x1) x [y0, y1); x0 == x1: none (no extinction, no pixel)
    };
    std::vector<TileRect> rects(n);
    std::vector<std::uint32_t> place(chunks * tiles, 0);  // counts, then each chunk's next place per tile
    // Pass 1: each sphere's tile rectangle, and each chunk's count per tile.
    parallel_for(chunks, threads, [&](std::size_t c, int) {
        std::uint32_t* count = place.data() + c * tiles;
        for (std::size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i) {
            const PixelRect& r = pixel_rects[order[i]];
            if (!(r.x0 < r.x1 && r.y0 < r.y1)) {
                rects[i] = TileRect{0, 0, 0, 0};
                continue;
            }
            const TileRect t{std::uint32_t(r.x0) / tile_size, std::uint32_t(r.y0) / tile_size,
                             (std::uint32_t(r.x1) + tile_size - 1) / tile_size, (std::uint32_t(r.y1) + tile_size - 1) / tile_size};
            rects[i] = t;
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
            const TileRect& t = rects[i];
            if (t.x0 == t.x1) continue;
            const std::uint32_t sphere = order[i];
            const std::uint32_t bits = std::bit_cast<std::uint32_t>(float(bound[sphere]));
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
