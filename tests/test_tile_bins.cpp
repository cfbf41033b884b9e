// The tiles method's binning (render/tile_bins.h): conservative (every sphere a pixel ray meets is
// listed in that pixel's tile), ordered (each tile keeps the order given), and tight (a sphere is
// not listed in tiles far from it).
#include "render/nearest_bounds.h"
#include "render/ray_box.h"
#include "render/tile_bins.h"
#include "sim/camera_rays.h"
#include "sim/smoke_cloud_scene.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <set>

namespace brume {
namespace {

bool ray_meets(const Sphere& s, const glm::dvec3& eye, const glm::dvec3& dir) {
    const glm::dvec3 oc = eye - s.center;
    const double b = glm::dot(oc, dir);
    const glm::dvec3 perp = oc - b * dir;
    const double disc = s.radius * s.radius - glm::dot(perp, perp);
    if (disc < 0.0) return false;
    const double far = -b + std::sqrt(disc);
    return far > 0.0;  // some of the chord lies ahead of the eye
}

std::vector<std::uint32_t> identity_order(std::size_t n) {
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    return order;
}

// Every (pixel, sphere) pair whose ray meets the sphere is in the pixel's tile list.
void expect_conservative(const Scene& scene, int w, int h, std::uint32_t tile) {
    std::vector<double> bound;
    nearest_event_bounds(scene, bound);
    TileBins bins;
    bin_spheres(scene, w, h, tile, identity_order(scene.spheres.size()), bound, bins);
    ASSERT_EQ(bins.tiles_x, (w + tile - 1) / tile);
    ASSERT_EQ(bins.tiles_y, (h + tile - 1) / tile);
    ASSERT_EQ(bins.entries.size(), 2 * (bins.entry_count() + 1));
    const CameraRays rays = make_camera_rays(scene.camera);
    std::uint64_t missing = 0, pairs = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::uint32_t t = std::uint32_t(y) / tile * bins.tiles_x + std::uint32_t(x) / tile;
            std::set<std::uint32_t> listed;
            for (std::uint32_t e = bins.first[t]; e < bins.first[t + 1]; ++e) listed.insert(bins.entries[2 * e]);
            const glm::dvec3 dir = rays.direction(x + 0.5, y + 0.5);
            for (std::uint32_t k = 0; k < scene.spheres.size(); ++k) {
                if (!(scene.spheres[k].extinction > 0.0) || !ray_meets(scene.spheres[k], rays.eye, dir)) continue;
                ++pairs;
                if (!listed.count(k)) ++missing;
            }
        }
    EXPECT_GT(pairs, 0u);
    EXPECT_EQ(missing, 0u) << "of " << pairs << " (pixel, sphere) pairs";
}

TEST(TileBins, EverySphereARayMeetsIsListedInItsTile) {
    // Random overlapping spheres, some around the eye and beside its plane, and a smoke cloud.
    expect_conservative(testing::random_scene(96, 72, 300, 3, false), 96, 72, 8);
    expect_conservative(make_smoke_cloud_scene(2000, 100, 60), 100, 60, 8);
    Scene around = testing::small_scene(64, 48);
    around.spheres.push_back(testing::sphere(around.camera.position, 0.5, 1.0, {0.5, 0.5, 0.5}));
    around.spheres.push_back(testing::sphere(around.camera.position + glm::dvec3(0.3, 0.0, 0.0), 0.4, 1.0, {0.5, 0.5, 0.5}));
    expect_conservative(around, 64, 48, 8);
}

TEST(TileBins, ImagesThatAreNotWholeTilesAndOtherTileSizes) {
    const Scene s = testing::random_scene(77, 53, 120, 11, false);
    expect_conservative(s, 77, 53, 8);
    expect_conservative(s, 77, 53, 16);
    expect_conservative(s, 77, 53, 1);
}

// Each tile lists its spheres in the order given, each with its bound, and `longest` is the longest list.
void expect_ordered(const TileBins& bins, const std::vector<std::uint32_t>& order, const std::vector<double>& bound) {
    std::vector<std::uint32_t> rank(bound.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
    std::uint32_t longest = 0;
    std::uint64_t misplaced = 0, wrong_bound = 0;
    for (std::uint32_t t = 0; t < bins.tile_count(); ++t) {
        longest = std::max(longest, bins.first[t + 1] - bins.first[t]);
        for (std::uint32_t e = bins.first[t]; e < bins.first[t + 1]; ++e) {
            const std::uint32_t k = bins.entries[2 * e];
            if (bins.entries[2 * e + 1] != std::bit_cast<std::uint32_t>(float(bound[k]))) ++wrong_bound;
            if (e > bins.first[t] && !(rank[bins.entries[2 * e - 2]] < rank[k])) ++misplaced;
        }
    }
    EXPECT_EQ(misplaced, 0u);
    EXPECT_EQ(wrong_bound, 0u);
    EXPECT_EQ(bins.longest, longest);
    // The sentinel after the last tile lies past every distance.
    EXPECT_GT(std::bit_cast<float>(bins.entries.back()), 1e38f);
}

// A smoke cloud of n spheres, its bounds, and its spheres near to far by them.
struct SortedCloud {
    Scene scene;
    std::vector<double> bound;
    std::vector<std::uint32_t> order;
};
SortedCloud sorted_cloud(std::size_t n, int w, int h) {
    SortedCloud c{make_smoke_cloud_scene(n, w, h), {}, {}};
    nearest_event_bounds(c.scene, c.bound);
    c.order = identity_order(c.bound.size());
    std::sort(c.order.begin(), c.order.end(), [&](std::uint32_t a, std::uint32_t b) { return c.bound[a] < c.bound[b]; });
    return c;
}

TEST(TileBins, EachTileKeepsTheOrderGivenWithItsBounds) {
    const SortedCloud c = sorted_cloud(3000, 64, 48);
    TileBins bins;
    bin_spheres(c.scene, 64, 48, 8, c.order, c.bound, bins);
    expect_ordered(bins, c.order, c.bound);
}

// The binning runs in chunks of the order over threads (a stable counting sort): enough spheres for
// several chunks give the same bins, in order, on one thread and on several.
TEST(TileBins, ManyChunksOnAnyNumberOfThreadsGiveTheSameOrderedBins) {
    const SortedCloud c = sorted_cloud(150000, 96, 54);
    const auto& [s, bound, order] = c;
    TileBins one;
    bin_spheres(s, 96, 54, 8, order, bound, one, 1);
    expect_ordered(one, order, bound);
    EXPECT_GT(one.entry_count(), order.size());  // spheres over tile borders are listed more than once
    for (int threads : {2, 3, 8}) {
        TileBins many;
        bin_spheres(s, 96, 54, 8, order, bound, many, threads);
        EXPECT_EQ(many.first, one.first) << threads << " threads";
        EXPECT_EQ(many.entries, one.entries) << threads << " threads";
        EXPECT_EQ(many.longest, one.longest) << threads << " threads";
    }
}

TEST(TileBins, ASmallSphereIsListedOnlyNearItsImage) {
    Scene s = testing::small_scene(128, 128);
    const CameraRays rays = make_camera_rays(s.camera);
    // A sphere seen at the centre of the image, a few pixels across.
    s.spheres.push_back(testing::sphere(rays.eye + 5.0 * rays.forward, 0.05, 1.0, {0.5, 0.5, 0.5}));
    std::vector<double> bound;
    nearest_event_bounds(s, bound);
    TileBins bins;
    bin_spheres(s, 128, 128, 8, {0}, bound, bins);
    EXPECT_GE(bins.entry_count(), 1u);
    EXPECT_LE(bins.entry_count(), 4u);  // the four tiles around the image centre at most
    PixelRect r;
    ASSERT_TRUE(sphere_pixel_rect(s.spheres[0], s.camera, 128, 128, r));
    EXPECT_LE(r.x0, 64);
    EXPECT_GE(r.x1, 64);
    EXPECT_LT(r.x1 - r.x0, 20);
}

TEST(TileBins, SpheresBehindTheEyeOrWithoutMediumAreLeftOut) {
    Scene s = testing::small_scene(64, 64);
    const CameraRays rays = make_camera_rays(s.camera);
    s.spheres.push_back(testing::sphere(rays.eye - 3.0 * rays.forward, 1.0, 1.0, {0.5, 0.5, 0.5}));
    s.spheres.push_back(testing::sphere(rays.eye + 3.0 * rays.forward, 1.0, 0.0, {0.5, 0.5, 0.5}));
    std::vector<double> bound;
    nearest_event_bounds(s, bound);
    TileBins bins;
    bin_spheres(s, 64, 64, 8, {0, 1}, bound, bins);
    EXPECT_EQ(bins.entry_count(), 0u);
}

// hull_pixel_rect (trace's culling of box shadows by tile): every pixel whose centre ray meets a box
// lies in the rectangle of its corners' hull, the rectangle is not the whole image for a small box in
// view, and a hull reaching behind the eye takes the whole image.
TEST(TileBins, AHullsRectangleHoldsEveryPixelWhoseRayMeetsIt) {
    Camera camera;
    camera.width = 96;
    camera.height = 64;
    const CameraRays rays = make_camera_rays(camera);
    const Box boxes[] = {{{-0.3, 0.1, -0.4}, {0.2, 0.6, 0.1}}, {{0.8, -0.5, -2.0}, {1.4, 0.0, -1.2}},
                         {{-2.0, 0.9, 1.0}, {-1.5, 1.3, 2.5}}};
    for (const Box& box : boxes) {
        glm::dvec3 corners[8];
        for (int c = 0; c < 8; ++c)
            corners[c] = glm::dvec3((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                                    (c & 4) ? box.max.z : box.min.z);
        PixelRect rect;
        ASSERT_TRUE(hull_pixel_rect(corners, 8, camera, camera.width, camera.height, rect));
        EXPECT_LT((rect.x1 - rect.x0) * (rect.y1 - rect.y0), camera.width * camera.height);
        int meeting = 0;
        for (int y = 0; y < camera.height; ++y)
            for (int x = 0; x < camera.width; ++x) {
                if (!std::isfinite(ray_box_distance(box, rays.eye, rays.direction(x + 0.5, y + 0.5)))) continue;
                ++meeting;
                EXPECT_TRUE(x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1) << x << ", " << y;
            }
        EXPECT_GT(meeting, 0);
    }
    // A corner behind the eye: its projection is unbounded.
    const glm::dvec3 behind[] = {{0.0, 0.5, 0.0}, {0.0, 1.0, 9.0}};
    PixelRect rect;
    ASSERT_TRUE(hull_pixel_rect(behind, 2, camera, camera.width, camera.height, rect));
    EXPECT_EQ(rect.x0, 0);
    EXPECT_EQ(rect.y0, 0);
    EXPECT_EQ(rect.x1, camera.width);
    EXPECT_EQ(rect.y1, camera.height);
}

}  // namespace
}  // namespace brume
