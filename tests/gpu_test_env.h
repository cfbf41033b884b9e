// Shared set-up for GPU tests: one lavapipe device per test program with the validation layer on,
// and a check after every test that it reported nothing (any message fails the test).
#pragma once

#include "render/image_compare.h"
#include "render/reference.h"
#include "render/vk/device.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

namespace brume::testing {

class GpuTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (device_) return;
        // Only lavapipe's driver is loaded (GUIDE section 5): other installed ICDs stay out of the way.
        const char* lavapipe = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
        setenv("VK_DRIVER_FILES", lavapipe, 1);
        setenv("VK_ICD_FILENAMES", lavapipe, 1);
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
// GUIDE/issue: the exact method matches the reference to 1e-4 of the image's peak.
inline constexpr double kRelTol = 1e-4;

// Compares with the reference at the float-conditioning tolerance; returns the diff for messages.
inline ImageDiff compare_with_reference(const Image& gpu, const Scene& scene) {
    const Image ref = render_reference(scene);
    const Image tol = reference_tolerance(scene, kRayRelError);
    return compare_images(gpu, ref, kRelTol, &tol);
}

}  // namespace brume::testing
