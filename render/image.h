// A linear-radiance RGB image: what every method produces and every output writer consumes.
#pragma once

#include <cstddef>
#include <vector>

namespace brume {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // row-major, top row first, 3 floats per pixel

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.0f) {}

    float* pixel(int i, int j) { return &rgb[(std::size_t(j) * width + i) * 3]; }
    const float* pixel(int i, int j) const { return &rgb[(std::size_t(j) * width + i) * 3]; }
};

}  // namespace brume
