#include "render/pixel_hull.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace brume {

PixelHull::PixelHull(const glm::dvec2* points, int count, double pad) {
    if (count < 3) return;  // no area: the rectangle decides
    std::vector<glm::dvec2> p(points, points + count);
    std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    const auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    // Andrew's monotone chain: the lower chain, then the upper, each turning one way.
    std::vector<glm::dvec2> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
        hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
        hull[k++] = p[i];
    }
    hull.resize(k - 1);  // the last point is the first
    if (hull.size() < 3) return;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
        glm::dvec2 n(b.y - a.y, a.x - b.x);  // outward for the chain's turn
        const double length = glm::length(n);
        if (!(length > 0.0)) continue;
        n /= length;
        double support = -std::numeric_limits<double>::infinity();
        for (const glm::dvec2& q : hull) support = std::max(support, glm::dot(n, q));
        edges_.push_back(Edge{n, support + pad});
    }
}

bool PixelHull::may_reach(double x0, double y0, double x1, double y1) const {
    for (const Edge& e : edges_) {
        // The rectangle's corner furthest against the normal: if even it lies beyond the support,
        // the whole rectangle does.
        const double least = std::min(e.normal.x * x0, e.normal.x * x1) + std::min(e.normal.y * y0, e.normal.y * y1);
        if (least > e.support) return false;
    }
    return true;
}

}  // namespace brume
