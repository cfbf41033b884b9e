// Comparing a method's image with the reference: the numbers tests assert on and benchmarks chart.
#pragma once

#include "render/image.h"

#include <cstddef>
#include <string>

namespace brume {

struct ImageDiff {
    double peak = 0;         // largest finite channel value of the reference
    double max_abs = 0;      // largest |test - reference| over channels
    double rmse = 0;         // over all channels
    double psnr_db = 0;      // 20 log10(peak / rmse); +inf when identical
    double max_excess = 0;   // largest (|a - b| - allowed) / peak: <= 0 when every channel is within tolerance
    std::size_t pixels_over = 0;  // pixels with at least one channel over its allowance
    int worst_i = -1, worst_j = -1;  // the pixel holding max_excess
};

// A channel is "over" when |a - b| > rel_tol * peak + (tolerance ? tolerance channel : 0). NaN in either
// image (or an Inf against anything) counts as an infinite difference: over, and max_excess, max_abs and
// rmse become +inf. max_excess is divided by peak, or by 1 when the reference is black.
// Throws std::invalid_argument when the sizes differ.
ImageDiff compare_images(const Image& test, const Image& reference, double rel_tol, const Image* tolerance = nullptr);

// One line, for test failure messages.
std::string describe(const ImageDiff& diff);

}  // namespace brume
