// Image files (README.md, "Tour", outputs): linear float EXR for compositing and tests, exposed sRGB
// PNG for people. Every write goes to a temporary file beside the target and is renamed over it only
// once complete, so an interrupted or failed write never leaves a partial file and never damages an
// existing one.
#pragma once

#include "render/image.h"

#include <filesystem>
#include <stdexcept>

namespace brume {

// what() names the file and the reason, e.g. "cannot write out/a.exr: No such file or directory".
class ImageIoError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Linear radiance as 32-bit FLOAT R, G, B channels, written exactly as given: no tone mapping, and
// NaN or Inf pixels are kept (they are evidence, not noise).
void write_exr(const Image& image, const std::filesystem::path& path);

// Reads the R, G and B channels as float; a missing channel reads as 0.
Image read_exr(const std::filesystem::path& path);

// 8-bit sRGB: multiply by 2^exposure_stops, apply the sRGB transfer function, clamp to [0, 1], round.
// NaN maps to 0.
void write_png(const Image& image, const std::filesystem::path& path, double exposure_stops = 0.0);

// The exact piecewise sRGB transfer function (IEC 61966-2-1), linear to encoded, for values in [0, 1].
float srgb_encode(float linear);

// The 8-bit code write_png writes for one channel: times exposure_scale (2^stops), the sRGB transfer,
// clamped, rounded; NaN is 0. Presenters' tone-map pass matches it (tests/test_gpu_frame_path.cpp).
unsigned char png_code(float linear, double exposure_scale);

}  // namespace brume
