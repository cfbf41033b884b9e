// Per-channel comparison in double precision, so that the statistics themselves add no rounding to speak of.
#include "render/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace brume {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void check_size(const Image& image, const Image& reference, const char* what) {
    const std::size_t expected = std::size_t(reference.width) * std::size_t(reference.height) * 3;
    if (image.width != reference.width || image.height != reference.height || image.rgb.size() != expected ||
        reference.rgb.size() != expected)
        throw std::invalid_argument(std::string("compare_images: ") + what + " is " + std::to_string(image.width) +
                                    "x" + std::to_string(image.height) + ", reference is " +
                                    std::to_string(reference.width) + "x" + std::to_string(reference.height));
}

}  // namespace

ImageDiff compare_images(const Image& test, const Image& reference, double rel_tol, const Image* tolerance) {
    check_size(test, reference, "test image");
    if (tolerance) check_size(*tolerance, reference, "tolerance image");

    ImageDiff d;
    for (const float v : reference.rgb)
        if (std::isfinite(v)) d.peak = std::max(d.peak, double(v));
    const double norm = d.peak > 0.0 ? d.peak : 1.0;
    const double base_allowance = rel_tol * d.peak;

    double sum_sq = 0.0;
    double worst = -kInf;
    const std::size_t pixels = std::size_t(reference.width) * std::size_t(reference.height);
    for (std::size_t p = 0; p < pixels; ++p) {
        bool over = false;
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t k = p * 3 + c;
            double diff = std::abs(double(test.rgb[k]) - double(reference.rgb[k]));
            if (std::isnan(diff)) diff = kInf;  // NaN is never "close"
            const double allowed = base_allowance + (tolerance ? double(tolerance->rgb[k]) : 0.0);
            if (!(diff <= allowed)) over = true;  // a NaN allowance admits nothing
            double excess = (diff - allowed) / norm;
            if (std::isnan(excess)) excess = kInf;
            d.max_abs = std::max(d.max_abs, diff);
            sum_sq += diff * diff;
            if (excess > worst) {
                worst = excess;
                d.worst_i = int(p % std::size_t(reference.width));
                d.worst_j = int(p / std::size_t(reference.width));
            }
        }
        if (over) ++d.pixels_over;
    }
    if (pixels > 0) {
        d.max_excess = worst;
        d.rmse = std::sqrt(sum_sq / double(pixels * 3));
    }
    d.psnr_db = d.rmse == 0.0 ? kInf : 20.0 * std::log10(d.peak / d.rmse);
    return d;
}

std::string describe(const ImageDiff& d) {
    char line[320];
    std::snprintf(line, sizeof line,
                  "max_excess %.4g of peak at pixel (%d, %d), %zu pixels over; max_abs %.4g, rmse %.4g, "
                  "psnr %.2f dB, peak %.6g",
                  d.max_excess, d.worst_i, d.worst_j, d.pixels_over, d.max_abs, d.rmse, d.psnr_db, d.peak);
    return line;
}

}  // namespace brume

namespace brume {

double temporal_error(const Image& method_now, const Image& method_prev, const Image& ref_now, const Image& ref_prev) {
    const std::size_t n = ref_now.rgb.size();
    if (method_now.rgb.size() != n || method_prev.rgb.size() != n || ref_prev.rgb.size() != n)
        throw std::invalid_argument("temporal_error: the four images must have the same size");
    double peak = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        if (std::isfinite(ref_now.rgb[k])) peak = std::max(peak, double(ref_now.rgb[k]));
        const double d = (double(method_now.rgb[k]) - method_prev.rgb[k]) - (double(ref_now.rgb[k]) - ref_prev.rgb[k]);
        sum += std::isfinite(d) ? std::abs(d) : std::numeric_limits<double>::infinity();
    }
    return n == 0 ? 0.0 : sum / double(n) / (peak > 0.0 ? peak : 1.0);
}

}  // namespace brume
