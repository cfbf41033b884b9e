#include "render/supersample.h"

#include <stdexcept>
#include <string>

namespace brume {

Scene supersampled_scene(const Scene& scene, int max_side) {
    const int k = scene.camera.supersample;
    if (k < 1) throw std::invalid_argument("supersample " + std::to_string(k) + ": must be at least 1");
    const long long w = static_cast<long long>(scene.camera.width) * k;
    const long long h = static_cast<long long>(scene.camera.height) * k;
    if (w > max_side || h > max_side)
        throw std::invalid_argument("supersample " + std::to_string(k) + " at " + std::to_string(scene.camera.width) +
                                    "x" + std::to_string(scene.camera.height) + " needs a " + std::to_string(w) + "x" +
                                    std::to_string(h) + " image, over the device's limit of " +
                                    std::to_string(max_side) + " pixels a side");
    Scene fine = scene;
    fine.camera.width = int(w);
    fine.camera.height = int(h);
    fine.camera.supersample = 1;
    return fine;
}

Image average_blocks(const Image& fine, int k) {
    if (k < 1 || fine.width % k != 0 || fine.height % k != 0)
        throw std::invalid_argument("average_blocks: " + std::to_string(fine.width) + "x" +
                                    std::to_string(fine.height) + " is not made of " + std::to_string(k) + "x" +
                                    std::to_string(k) + " blocks");
    if (k == 1) return fine;
    Image out(fine.width / k, fine.height / k);
    const double inv = 1.0 / (double(k) * double(k));
    for (int j = 0; j < out.height; ++j) {
        for (int i = 0; i < out.width; ++i) {
            double sum[3] = {0.0, 0.0, 0.0};
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const float* p = fine.pixel(i * k + a, j * k + b);
                    for (int c = 0; c < 3; ++c) sum[c] += p[c];
                }
            float* q = out.pixel(i, j);
            for (int c = 0; c < 3; ++c) q[c] = float(sum[c] * inv);
        }
    }
    return out;
}

}  // namespace brume
