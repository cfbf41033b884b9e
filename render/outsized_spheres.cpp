#include "render/outsized_spheres.h"

#include <algorithm>

namespace brume {

namespace {

// Every index into scene.spheres of a sphere with a medium over kOutsizedRadii times the median radius
// of those spheres, ascending; none where all of them are.
std::vector<std::size_t> over_the_limit(const Scene& scene) {
    std::vector<double> radii;
    for (const Sphere& sp : scene.spheres)
        if (sp.extinction > 0.0 && sp.radius > 0.0) radii.push_back(sp.radius);
    if (radii.empty()) return {};
    const std::size_t middle = radii.size() / 2;
    std::nth_element(radii.begin(), radii.begin() + std::ptrdiff_t(middle), radii.end());
    const double limit = kOutsizedRadii * radii[middle];
    std::vector<std::size_t> over;
    for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
        const Sphere& sp = scene.spheres[k];
        if (sp.extinction > 0.0 && sp.radius > limit) over.push_back(k);
    }
    if (over.size() >= radii.size()) return {};
    return over;
}

}  // namespace

std::size_t outsized_sphere_count(const Scene& scene) { return over_the_limit(scene).size(); }

std::vector<std::size_t> outsized_spheres(const Scene& scene) {
    std::vector<std::size_t> over = over_the_limit(scene);
    if (over.empty()) return {};
    // The largest first (ties in scene order), at most kMaxOutsized, then back in scene order.
    const auto radius = [&](std::size_t k) { return scene.spheres[k].radius; };
    std::stable_sort(over.begin(), over.end(), [&](std::size_t a, std::size_t b) { return radius(a) > radius(b); });
    over.resize(std::min<std::size_t>(over.size(), std::size_t(kMaxOutsized)));
    std::sort(over.begin(), over.end());
    return over;
}

}  // namespace brume
