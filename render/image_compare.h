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

namespace brume {

// The popping metric `brume bench` charts (README.md, "Methods compared") for one frame step: mean
// over pixels and channels of |(I_t - I_{t-1}) - (R_t - R_{t-1})|, divided by the reference frame's
// peak. An exact method scores the reference's own noise floor (about 0); a sorted method spikes
// where two particles swap order.
double temporal_error(const Image& method_now, const Image& method_prev, const Image& ref_now, const Image& ref_prev);

}  // namespace brume
