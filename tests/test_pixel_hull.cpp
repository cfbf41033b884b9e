// The convex hull of projected points that trace's tiles test box shadows against
// (render/pixel_hull.h): it never rejects a rectangle that a point of the hull lies in (convex
// combinations of the points, the pad included), and it rejects most of the rectangles beside a thin
// slanted hull that the hull's bounding rectangle holds. CPU only.
#include "render/pixel_hull.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace brume {
namespace {

TEST(PixelHull, NeverRejectsARectangleThatHoldsAPointOfTheHull) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-50.0, 150.0), unit(0.0, 1.0);
    int rejected = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const int count = 3 + trial % 14;
        std::vector<glm::dvec2> points(static_cast<std::size_t>(count));
        for (glm::dvec2& p : points) p = {coord(rng), coord(rng)};
        const double pad = trial % 2 == 0 ? 0.0 : 1.0;
        const PixelHull hull(points.data(), count, pad);
        for (int n = 0; n < 200; ++n) {
            // A point of the hull (a random convex combination), and a small rectangle around or beside it.
            glm::dvec2 q(0.0);
            double total = 0.0;
            std::vector<double> w(static_cast<std::size_t>(count));
            for (double& x : w) total += (x = unit(rng) * unit(rng));
            for (int k = 0; k < count; ++k) q += points[std::size_t(k)] * (w[std::size_t(k)] / total);
            const double size = 1.0 + 8.0 * unit(rng);
            const glm::dvec2 corner = q - glm::dvec2(size * unit(rng), size * unit(rng));
            ASSERT_TRUE(hull.may_reach(corner.x, corner.y, corner.x + size, corner.y + size)) << trial << " " << n;
            // The same rectangle moved off by up to 60 pixels: where the hull rejects it, no point of the
            // hull (a fine sample of combinations) lies inside it.
            const glm::dvec2 off = corner + glm::dvec2(120.0 * unit(rng) - 60.0, 120.0 * unit(rng) - 60.0);
            if (!hull.may_reach(off.x, off.y, off.x + size, off.y + size)) {
                ++rejected;
                for (int m = 0; m < 50; ++m) {
                    glm::dvec2 r(0.0);
                    double t = 0.0;
                    for (double& x : w) t += (x = unit(rng) * unit(rng) * unit(rng));
                    for (int k = 0; k < count; ++k) r += points[std::size_t(k)] * (w[std::size_t(k)] / t);
                    ASSERT_FALSE(r.x >= off.x - pad && r.x <= off.x + size + pad && r.y >= off.y - pad &&
                                 r.y <= off.y + size + pad)
                        << trial << " " << n;
                }
            }
        }
    }
    EXPECT_GT(rejected, 1000);  // the hull rejected rectangles: the test asked both ways
}

// A long thin band at 45 degrees, as a low sun's post casts: of the 8-pixel tiles of its bounding
// rectangle, the hull reaches only those along the diagonal.
TEST(PixelHull, ASlantedBandReachesFewOfItsRectanglesTiles) {
    const glm::dvec2 band[4] = {{0.0, 4.0}, {4.0, 0.0}, {200.0, 196.0}, {196.0, 200.0}};
    const PixelHull hull(band, 4, 1.0);
    int reached = 0, tiles = 0;
    for (int y = 0; y < 200; y += 8)
        for (int x = 0; x < 200; x += 8) {
            ++tiles;
            reached += hull.may_reach(x, y, x + 8, y + 8);
        }
    EXPECT_GE(reached, 25);          // every tile on the diagonal
    EXPECT_LE(reached, 3 * 25 + 2);  // and its neighbours at most
    EXPECT_EQ(tiles, 625);
    EXPECT_TRUE(PixelHull().may_reach(0, 0, 1, 1));  // no hull: the rectangle decides
}

}  // namespace
}  // namespace brume
