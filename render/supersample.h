// Supersampling for renderers that draw one ray per pixel (docs/accuracy.md): the scene is drawn at k times
// the camera's size, whose pixel centres are exactly the k x k sub-pixel ray positions
// (i + (a + 0.5) / k, j + (b + 0.5) / k) of the camera's pixels, and each k x k block is averaged.
#pragma once

#include "render/image.h"
#include "sim/scene.h"

namespace brume {

// The scene with camera.width and height multiplied by camera.supersample and supersample set to 1.
// Throws std::invalid_argument when the enlarged image would exceed max_side pixels on a side.
Scene supersampled_scene(const Scene& scene, int max_side);

// The mean of each k x k block of `fine`, whose sides must be multiples of k (summed in double).
Image average_blocks(const Image& fine, int k);

}  // namespace brume
