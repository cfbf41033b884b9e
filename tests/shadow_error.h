// The error of a shadowed image against the exact reference in the terms the shadow techniques state it
// (docs/accuracy.md): the mean over pixels and channels and the 99.9th percentile, both over the
// reference's peak.
#pragma once

#include "render/image.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace brume::testing {

struct ShadowError {
    double mean = 0.0, p999 = 0.0;
};

inline ShadowError shadow_error(const Image& img, const Image& ref) {
    double peak = 0.0;
    for (float v : ref.rgb) peak = std::max(peak, double(v));
    std::vector<double> e(img.rgb.size());
    double sum = 0.0;
    for (std::size_t k = 0; k < e.size(); ++k) {
        e[k] = std::abs(double(img.rgb[k]) - double(ref.rgb[k])) / peak;
        sum += e[k];
    }
    std::sort(e.begin(), e.end());
    return {sum / double(e.size()), e[std::min(e.size() - 1, std::size_t(0.999 * double(e.size())))]};
}

}  // namespace brume::testing
