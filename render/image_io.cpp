#include "render/image_io.h"

#include "render/atomic_file.h"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
// libstb.so carries the implementation; defining STB_IMAGE_WRITE_IMPLEMENTATION here would duplicate it.
#include <stb/stb_image_write.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace brume {

namespace {

namespace fs = std::filesystem;

std::string os_reason(int err) { return std::generic_category().message(err); }

[[noreturn]] void fail_write(const fs::path& path, const std::string& reason) {
    throw ImageIoError("cannot write " + path.string() + ": " + reason);
}

void check_image(const Image& image, const fs::path& path) {
    if (image.width < 1 || image.height < 1 ||
        image.rgb.size() != std::size_t(image.width) * std::size_t(image.height) * 3)
        fail_write(path, "the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                             " but holds " + std::to_string(image.rgb.size()) + " floats");
}

// Writes through the shared atomic writer, reporting failures as image errors.
void write_image_file(const fs::path& path, std::string_view bytes) {
    try {
        write_file_atomically(path, bytes);
    } catch (const FileWriteError& e) {
        throw ImageIoError(e.what());
    }
}

std::string encode_exr(const Image& image) {
    Imf::Header header(image.width, image.height);
    for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::StdOSStream stream;
    {
        // The output file writes its offset table when destroyed, so it must close before str().
        Imf::OutputFile out(stream, header);
        Imf::FrameBuffer frame;
        const std::size_t x_stride = 3 * sizeof(float);
        const std::size_t y_stride = x_stride * std::size_t(image.width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));  // only read
        frame.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), x_stride, y_stride));
        frame.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), x_stride, y_stride));
        frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), x_stride, y_stride));
        out.setFrameBuffer(frame);
        out.writePixels(image.height);
    }
    return stream.str();
}

double srgb_encode_exact(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

std::string encode_png(const Image& image, double exposure_stops, const fs::path& path) {
    if (!std::isfinite(exposure_stops)) fail_write(path, "exposure must be finite");
    if (image.width > std::numeric_limits<int>::max() / 3) fail_write(path, "the image is too wide for PNG");
    const double scale = std::exp2(exposure_stops);
    std::vector<unsigned char> pixels(image.rgb.size());
    for (int j = 0; j < image.height; ++j)
        for (int i = 0; i < image.width; ++i)
            for (int c = 0; c < 3; ++c) {
                const std::size_t k = (std::size_t(j) * std::size_t(image.width) + std::size_t(i)) * 3 + std::size_t(c);
                pixels[k] = png_code(image.rgb[k], scale, png_dither(i, j, c));
            }
    std::string bytes;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, pixels.data(), image.width * 3))
        fail_write(path, "PNG encoding failed");
    return bytes;
}

}  // namespace

float srgb_encode(float linear) { return static_cast<float>(srgb_encode_exact(linear)); }

// Written so that NaN lands on 0 and +Inf on 255.
unsigned char png_code(float linear, double exposure_scale, double dither) {
    const double v = double(linear) * exposure_scale;
    if (!(v > 0.0)) return 0;
    if (!(v < 1.0)) return 255;
    const double code = std::floor(srgb_encode_exact(v) * 255.0 + 0.5 + dither);
    return static_cast<unsigned char>(std::clamp(code, 0.0, 255.0));
}

double png_dither(int i, int j, int c) {
    // A 64-bit mix (the splitmix64 finaliser) of the position: no visible pattern, no state.
    std::uint64_t x = (std::uint64_t(std::uint32_t(i)) << 34) ^ (std::uint64_t(std::uint32_t(j)) << 2) ^
                      std::uint64_t(c) ^ 0x9e3779b97f4a7c15ull;
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return double(x >> 11) * 0x1.0p-53 - 0.5;
}

std::string exr_bytes(const Image& image, const fs::path& path) {
    check_image(image, path);
    try {
        return encode_exr(image);
    } catch (const std::exception& e) {
        fail_write(path, std::string("EXR encoding failed: ") + e.what());
    }
}

std::string png_bytes(const Image& image, const fs::path& path, double exposure_stops) {
    check_image(image, path);
    return encode_png(image, exposure_stops, path);
}

void write_exr(const Image& image, const fs::path& path) { write_image_file(path, exr_bytes(image, path)); }

Image read_exr(const fs::path& path) {
    const std::string name = path.string();
    // OpenEXR's own message for a missing file is wordy; the OS reason is what the user needs.
    const int probe = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (probe < 0) {
        const int err = errno;
        throw ImageIoError("cannot read " + name + ": " + os_reason(err));
    }
    ::close(probe);
    try {
        Imf::InputFile in(path.c_str());
        const Imath::Box2i window = in.header().dataWindow();
        const std::int64_t width = std::int64_t(window.max.x) - window.min.x + 1;
        const std::int64_t height = std::int64_t(window.max.y) - window.min.y + 1;
        // A corrupt header must not turn into a giant allocation: bound each side and the total.
        constexpr std::int64_t kMaxSide = 1 << 20;
        if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide || width * height > (1ll << 31))
            throw ImageIoError("cannot read " + name + ": unreasonable data window " + std::to_string(width) +
                               "x" + std::to_string(height));
        Image image(static_cast<int>(width), static_cast<int>(height));
        const std::size_t x_stride = 3 * sizeof(float);
        const std::size_t y_stride = x_stride * std::size_t(width);
        Imf::FrameBuffer frame;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, x_stride, y_stride));
        in.setFrameBuffer(frame);
        in.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const ImageIoError&) {
        throw;
    } catch (const std::exception& e) {
        throw ImageIoError("cannot read " + name + ": " + e.what());
    }
}

void write_png(const Image& image, const fs::path& path, double exposure_stops) {
    write_image_file(path, png_bytes(image, path, exposure_stops));
}

}  // namespace brume
