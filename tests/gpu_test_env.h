// Shared set-up for GPU tests: one lavapipe device per test program with the validation layer on,
// and a check after every test that it reported nothing (any message fails the test).
#pragma once

#include "test_scenes.h"

#include "render/image_compare.h"
#include "render/methods/method.h"
#include "render/reference.h"
#include "render/vk/device.h"
#include "sim/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace brume::testing {

// Loads only lavapipe's driver (Mesa's CPU Vulkan driver, the default device): other installed ICDs
// stay out of the way.
inline void force_lavapipe() {
    const char* lavapipe = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
    setenv("VK_DRIVER_FILES", lavapipe, 1);
    setenv("VK_ICD_FILENAMES", lavapipe, 1);
}

class GpuTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (device_) return;
        force_lavapipe();
        vk::DeviceOptions options;
        options.device_name = "llvmpipe";
        options.validate = true;
        device_ = std::make_unique<vk::Device>(options);
    }
    static void TearDownTestSuite() { device_.reset(); }
    void SetUp() override { ASSERT_TRUE(device_->validation_enabled()); }
    void TearDown() override {
        const auto messages = device_->take_validation_messages();
        for (const auto& m : messages) ADD_FAILURE() << m;
    }
    static vk::Device& device() { return *device_; }

private:
    static inline std::unique_ptr<vk::Device> device_;
};

// A float32 GPU can place its pixel rays only to about this relative precision (a few ulps of the
// direction and of the eye); near silhouettes and box edges the exact answer moves by that much.
inline constexpr double kRayRelError = 1e-6;
// The exact method matches the reference to 1e-4 of the image's peak (docs/accuracy.md).
inline constexpr double kRelTol = 1e-4;

// The reference image of a scene and its float-conditioning tolerance, computed once for tests that
// compare several methods with it.
struct ReferenceImage {
    explicit ReferenceImage(const Scene& scene, const ReferenceOptions& options = {})
        : image(render_reference(scene, options)), tolerance(reference_tolerance(scene, kRayRelError, options)) {}
    Image image;
    Image tolerance;
};

inline ImageDiff compare_with_reference(const Image& gpu, const ReferenceImage& ref) {
    return compare_images(gpu, ref.image, kRelTol, &ref.tolerance);
}

// Compares with the reference at the float-conditioning tolerance; returns the diff for messages.
inline ImageDiff compare_with_reference(const Image& gpu, const Scene& scene) {
    return compare_with_reference(gpu, ReferenceImage(scene));
}

// Bit for bit the same image.
inline bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

inline bool all_finite(const Image& img) {
    return std::all_of(img.rgb.begin(), img.rgb.end(), [](float v) { return std::isfinite(v); });
}

// Two frames of testing::intersecting_pair whose centres' depth order flips between them (a 2 mm step
// of one sphere), rendered by `method`: its popping (temporal_error, render/image_compare.h) against
// the reference's own step, and the two frames.
struct OrderFlip {
    Image before, after;
    double popping = 0.0;         // temporal error of the method's step
    double reference_step = 0.0;  // mean |R_t - R_t-1| / peak
};
inline OrderFlip flip_order(Method& method) {
    const Scene a = intersecting_pair(0.3, 2.5, 0.001, 0.0);
    Scene b = a;
    b.spheres[0].center.z = -0.001;
    OrderFlip f;
    f.before = method.render(a);
    f.after = method.render(b);
    const Image ra = render_reference(a), rb = render_reference(b);
    f.popping = temporal_error(f.after, f.before, rb, ra);
    f.reference_step = temporal_error(rb, ra, ra, ra);
    return f;
}

}  // namespace brume::testing
