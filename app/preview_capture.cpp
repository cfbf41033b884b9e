#include "app/preview_capture.h"

#include "render/atomic_file.h"

#include <stb/stb_image_write.h>

#include <stdexcept>
#include <string>

namespace brume::app {

void write_capture_png(const std::vector<std::uint8_t>& rgba, VkExtent2D extent, const std::filesystem::path& path) {
    if (rgba.size() != std::size_t(extent.width) * extent.height * 4 || rgba.empty())
        throw std::runtime_error("capture " + path.string() + ": no frame was captured");
    // The window is opaque: alpha carries nothing, and RGB PNGs compare with brume play's directly.
    std::vector<std::uint8_t> rgb(std::size_t(extent.width) * extent.height * 3);
    for (std::size_t p = 0, n = std::size_t(extent.width) * extent.height; p < n; ++p)
        for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = rgba[p * 4 + c];
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, int(extent.width), int(extent.height), 3, rgb.data(),
                                int(extent.width) * 3))
        throw std::runtime_error("capture " + path.string() + ": PNG encoding failed");
    write_file_atomically(path, bytes);
}

}  // namespace brume::app
