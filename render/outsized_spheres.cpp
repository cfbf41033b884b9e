#include "render/outsized_spheres.h"

#include <algorithm>

namespace brume {

namespace {

// Every index of `radii` over kOutsizedRadii times the median radius, ascending; none where all are.
std::vector<std::size_t> over_the_limit(std::span<const double> radii) {
    if (radii.empty()) return {};
    std::vector<double> sorted(radii.begin(), radii.end());
    const std::size_t middle = sorted.size() / 2;
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(middle), sorted.end());
    const double limit = kOutsizedRadii * sorted[middle];
    std::vector<std::size_t> over;
    for (std::size_t k = 0; k < radii.size(); ++k)
        if (radii[k] > limit) over.push_back(k);
    if (over.size() >= radii.size()) return {};
    return over;
}

}  // namespace

std::size_t outsized_sphere_count(std::span<const double> radii) { return over_the_limit(radii).size(); }

std::vector<std::size_t> outsized_spheres(std::span<const double> radii) {
    std::vector<std::size_t> over = over_the_limit(radii);
    if (over.empty()) return {};
    // The largest first (ties in scene order), at most kMaxOutsized, then back in scene order.
    std::stable_sort(over.begin(), over.end(), [&](std::size_t a, std::size_t b) { return radii[a] > radii[b]; });
    over.resize(std::min<std::size_t>(over.size(), std::size_t(kMaxOutsized)));
    std::sort(over.begin(), over.end());
    return over;
}

}  // namespace brume
