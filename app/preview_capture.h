// A capture of the window as it is shown (the frame tone-mapped by the GPU, with the panel), for
// documentation and for the test that the window shows what `brume play` writes. A screenshot
// (PreviewSession::screenshot) is the frame itself; a capture is the screen.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace brume::app {

// Writes RGBA pixels (top row first) as an 8-bit RGB PNG, atomically. Throws FileWriteError.
void write_capture_png(const std::vector<std::uint8_t>& rgba, VkExtent2D extent, const std::filesystem::path& path);

}  // namespace brume::app
