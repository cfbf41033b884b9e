// The convex hull of a few points' projections, in pixel coordinates (render/tile_bins.h
// project_to_pixels), for a test of which tiles of pixels it may reach that is tighter than its
// bounding rectangle: trace's box shadows within the media (render/fast_tracer.cpp). A low sun's posts
// cast long, thin shadows across the image at a slant; their rectangles held many tiles whose rays
// never meet them, and each of those rays took the shadow's interval (BoxShadowVolume::interval).
#pragma once

#include <glm/vec2.hpp>

#include <vector>

namespace brume {

class PixelHull {
public:
    PixelHull() = default;  // no hull: may_reach answers true (the caller keeps its rectangle's answer)
    // The hull of points[0, count) (pixel coordinates), grown by `pad` pixels on every side.
    PixelHull(const glm::dvec2* points, int count, double pad);

    // False only where the hull lies wholly outside [x0, x1] x [y0, y1] (pixel coordinates) by one of
    // its own edges: a rectangle that it misses by an axis of the image alone is the bounding
    // rectangle's to reject.
    bool may_reach(double x0, double y0, double x1, double y1) const;

private:
    // Counter-clockwise in pixel coordinates (x right, y down): each edge's outward normal, and the
    // largest n . p over the hull's points (its support), pad included.
    struct Edge {
        glm::dvec2 normal;
        double support;
    };
    std::vector<Edge> edges_;
};

}  // namespace brume
