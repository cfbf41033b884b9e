#include "app/preview_compare.h"

#include <cmath>
#include <stdexcept>

namespace brume::app {

Image compose_comparison(const Image& method, const Image& other, CompareMode mode) {
    if (method.width != other.width || method.height != other.height)
        throw std::invalid_argument("compose_comparison: the two frames differ in size");
    Image out(method.width, method.height);
    const int split = method.width / 2;
    for (int j = 0; j < method.height; ++j)
        for (int i = 0; i < method.width; ++i) {
            const float* a = method.pixel(i, j);
            const float* b = other.pixel(i, j);
            float* o = out.pixel(i, j);
            for (int c = 0; c < 3; ++c) {
                if (mode == CompareMode::Difference)
                    o[c] = std::abs(a[c] - b[c]) * kDifferenceGain;
                else
                    o[c] = i < split ? a[c] : i == split ? 1.0f : b[c];
            }
        }
    return out;
}

}  // namespace brume::app
