#include "app/preview_heat_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace brume::app {
namespace {

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

std::array<float, 3> heat_colour(double t) {
    static constexpr float stops[5][3] = {{0.1f, 0.2f, 1.0f}, {0.0f, 0.9f, 1.0f}, {0.1f, 0.9f, 0.1f},
                                          {1.0f, 0.9f, 0.0f}, {1.0f, 0.1f, 0.0f}};
    t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4.0;
    const int k = std::min(3, int(t));
    const float f = float(t - k);
    return {stops[k][0] + f * (stops[k + 1][0] - stops[k][0]), stops[k][1] + f * (stops[k + 1][1] - stops[k][1]),
            stops[k][2] + f * (stops[k + 1][2] - stops[k][2])};
}

Image overlay_list_heat_map(const Image& frame, const Image& counts, double longest, double exposure_stops) {
    if (frame.width != counts.width || frame.height != counts.height)
        throw std::invalid_argument("overlay_list_heat_map: the frame and the counts differ in size");
    // The ramp's 256 colours in linear radiance before the exposure the tone map applies.
    const double unexpose = std::exp2(-exposure_stops);
    std::array<std::array<float, 3>, 256> linear{};
    for (int k = 0; k < 256; ++k) {
        const std::array<float, 3> c = heat_colour(k / 255.0);
        for (int ch = 0; ch < 3; ++ch) linear[std::size_t(k)][std::size_t(ch)] = float(srgb_to_linear(c[std::size_t(ch)]) * unexpose);
    }
    const double span = std::max(longest - 1.0, 1.0);
    Image out = frame;
    for (int j = 0; j < frame.height; ++j)
        for (int i = 0; i < frame.width; ++i) {
            const double n = counts.pixel(i, j)[0];
            if (!(n > 0.0)) continue;
            const int k = int(std::lround(std::clamp((n - 1.0) / span, 0.0, 1.0) * 255.0));
            float* o = out.pixel(i, j);
            for (int ch = 0; ch < 3; ++ch)
                o[ch] = (1.0f - kHeatMapOpacity) * o[ch] + kHeatMapOpacity * linear[std::size_t(k)][std::size_t(ch)];
        }
    return out;
}

}  // namespace brume::app
