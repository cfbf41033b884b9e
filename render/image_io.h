// Image files (README.md, "Tour", outputs): linear float EXR for compositing and tests, exposed sRGB
// PNG for people. Every write goes to a temporary file beside the target and is renamed over it only
// once complete, so an interrupted or failed write never leaves a partial file and never damages an
// existing one.
#pragma once

#include "render/image.h"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace brume {

// what() names the file and the reason, e.g. "cannot write out/a.exr: No such file or directory".
class ImageIoError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Linear radiance as 32-bit FLOAT R, G, B channels, written exactly as given: no tone mapping, and
// NaN or Inf pixels are kept (they are evidence, not noise).
void write_exr(const Image& image, const std::filesystem::path& path);

// The bytes write_exr and write_png would write, for outputs committed together (render/output_set.h).
// `path` only names the file in an ImageIoError.
std::string exr_bytes(const Image& image, const std::filesystem::path& path);
std::string png_bytes(const Image& image, const std::filesystem::path& path, double exposure_stops = 0.0);

// Reads the R, G and B channels as float; a missing channel reads as 0.
Image read_exr(const std::filesystem::path& path);

// 8-bit sRGB: multiply by 2^exposure_stops, apply the sRGB transfer function, clamp to [0, 1], round after
// adding png_dither's offset for the pixel and channel, so smooth gradients do not band into 8-bit steps.
// NaN maps to 0; black and saturated values are not dithered. The EXR writer is unaffected.
void write_png(const Image& image, const std::filesystem::path& path, double exposure_stops = 0.0);

// The exact piecewise sRGB transfer function (IEC 61966-2-1), linear to encoded, for values in [0, 1].
float srgb_encode(float linear);

// The 8-bit code for one channel: times exposure_scale (2^stops), the sRGB transfer, clamped, then
// floor(encoded * 255 + 0.5 + dither); NaN is 0, and values at or beyond 0 and 1 give 0 and 255 whatever
// the dither. With dither 0 it is plain rounding, which presenters' tone-map pass matches
// (tests/test_gpu_frame_path.cpp); write_png passes png_dither.
unsigned char png_code(float linear, double exposure_scale, double dither = 0.0);

// write_png's dither offset for pixel (i, j), channel c: uniform in [-0.5, 0.5) code values, from a
// hash of the position, so a file's bytes depend on its pixels alone (the same image, the same file).
double png_dither(int i, int j, int c);

}  // namespace brume
