// `screendoor`, object-space screen-door transparency with S x S supersampling (Sen, Chemudugunta &
// Gopi, "Silhouette-Opaque Transparency Rendering"): exact where the answer is binary (opaque spheres),
// converging as S grows where it is not, with a mask that moves with its particle.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/screendoor.h"

#include <cmath>
#include <stdexcept>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;
using testing::kRayRelError;
using testing::kRelTol;

Scene small_scene(int w = 128, int h = 96) { return testing::small_scene(w, h); }

using testing::sphere;

// Mean of each S x S block: what the method's box filter computes from exact sub-samples.
Image box_filter(const Image& big, int samples) {
    Image small(big.width / samples, big.height / samples);
    for (int j = 0; j < small.height; ++j)
        for (int i = 0; i < small.width; ++i)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (int y = 0; y < samples; ++y)
                    for (int x = 0; x < samples; ++x) sum += big.pixel(i * samples + x, j * samples + y)[c];
                small.pixel(i, j)[c] = float(sum / (samples * samples));
            }
    return small;
}

Scene scaled(Scene s, int samples) {
    s.camera.width *= samples;
    s.camera.height *= samples;
    return s;
}

// Mean absolute difference over channels, relative to the reference's peak.
double mean_error(const Image& img, const Image& ref) {
    double peak = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < ref.rgb.size(); ++k) {
        peak = std::max(peak, double(ref.rgb[k]));
        sum += std::abs(double(img.rgb[k]) - ref.rgb[k]);
    }
    return sum / double(ref.rgb.size()) / peak;
}

// Opaque spheres (alpha = 1 wherever the chord is longer than about 1e-3), one hiding part of another,
// one sliced by a wall: nearest-wins is the exact answer, the binary mask plays no part. (Where two
// such spheres intersect, rays whose entries differ by less than about 1 / tau cross both media: the
// reference mixes their colours there and nearest-wins does not.)
Scene opaque_scene(bool with_boxes) {
    Scene s = small_scene();
    s.spheres.push_back(sphere({-0.4, 0.1, 0.0}, 0.9, 1e4, {0.9, 0.3, 0.2}));
    s.spheres.push_back(sphere({0.5, -0.1, 1.4}, 0.7, 1e4, {0.2, 0.4, 0.9}));  // in front of sphere 0
    s.spheres.push_back(sphere({1.0, 0.6, -1.5}, 0.6, 1e4, {0.3, 0.9, 0.3}));
    if (with_boxes) {
        s.boxes.push_back(Box{{-20, -20, -12}, {20, 20, -10}, {0.3, 0.25, 0.2}});
        s.boxes.push_back(Box{{0.6, -3, -3}, {3, 3, -1.2}, {0.1, 0.1, 0.5}});  // slices sphere 2
    }
    return s;
}

class Screendoor : public GpuTest {};

TEST_F(Screendoor, OpaqueSpheresAtOneSampleMatchReference) {
    // S = 1 samples exactly the reference's pixel-centre rays.
    const Scene s = opaque_scene(true);
    ScreendoorMethod door(device(), 1);
    FrameStats stats;
    const Image img = door.render(s, &stats);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    ASSERT_EQ(stats.passes.size(), 3u);
    EXPECT_EQ(stats.memory_bytes, ScreendoorMethod::target_bytes(1, 128, 96));
}

TEST_F(Screendoor, OpaqueSpheresMatchTheBoxFilteredSupersampledReference) {
    // At S > 1 each sub-sample is the reference's ray at S x the resolution; the box filter of those
    // is the exact answer (the opaque pass, at the image's resolution, plays no part without boxes).
    const Scene s = opaque_scene(false);
    for (int samples : {2, 3, 4}) {
        ScreendoorMethod door(device(), samples);
        const Image img = door.render(s);
        const Scene big = scaled(s, samples);
        const Image ref = box_filter(render_reference(big), samples);
        const Image tol = box_filter(reference_tolerance(big, kRayRelError), samples);
        const ImageDiff d = compare_images(img, ref, kRelTol, &tol);
        EXPECT_EQ(d.pixels_over, 0u) << "S " << samples << ": " << describe(d);
        // and it is not the one-sample image: silhouettes are anti-aliased
        const ImageDiff aliased = compare_with_reference(img, s);
        EXPECT_GT(aliased.pixels_over, 50u) << "S " << samples;
    }
}

// Translucent spheres stacked in depth (disjoint depth ranges, overlapping on screen), where
// back-to-front "over" is exact: screen-door's expected image is the reference, its error is noise.
Scene soft_scene() {
    Scene s = small_scene();
    s.boxes.push_back(Box{{-20, -20, -12}, {20, 20, -10}, {0.3, 0.25, 0.2}});
    s.spheres.push_back(sphere({0.2, 0.1, -3.2}, 1.2, 0.6, {0.9, 0.3, 0.2}));
    s.spheres.push_back(sphere({-0.3, -0.1, 2.6}, 0.5, 1.0, {0.2, 0.8, 0.3}));
    s.spheres.push_back(sphere({0.0, 0.2, 0.3}, 0.9, 0.5, {0.3, 0.4, 0.95}));
    s.spheres.push_back(sphere({0.5, -0.3, -1.3}, 0.6, 1.0, {0.95, 0.9, 0.3}));
    s.spheres.push_back(sphere({-0.4, 0.3, 1.6}, 0.3, 0.8, {0.8, 0.8, 0.8}));
    return s;
}

TEST_F(Screendoor, ErrorFallsAsSamplesGrow) {
    const Scene s = soft_scene();
    const Image ref = render_reference(s);
    double error[9] = {};
    for (int samples : {1, 2, 4, 8}) {
        ScreendoorMethod door(device(), samples);
        error[samples] = mean_error(door.render(s), ref);
    }
    // About 1/S for a binomial count of S^2 independent sub-samples.
    EXPECT_LT(error[4], 0.5 * error[1]) << "S=1 " << error[1] << ", S=4 " << error[4];
    EXPECT_LT(error[8], error[4]) << "S=4 " << error[4] << ", S=8 " << error[8];
    EXPECT_LT(error[2], error[1]);
    EXPECT_LT(error[8], 0.02);
    std::printf("screendoor mean |error| / peak: S=1 %.4g, S=2 %.4g, S=4 %.4g, S=8 %.4g\n", error[1], error[2],
                error[4], error[8]);
}

TEST_F(Screendoor, TwoLayersCoverLikeIndependentMasks) {
    // Two large, nearly uniform layers of alpha about 0.5, one behind the other: independent masks
    // show the back layer on about 0.5 * 0.5 of the sub-samples. One shared mask would show it on none
    // (or on half), the classic screen-door failure that object-space masks avoid.
    Scene s = small_scene(64, 48);
    s.camera.fov_y_deg = 10.0;  // the centre of two big spheres: chords nearly constant over the view
    s.lighting.background = {0, 0, 0};
    const double chord_front = 2.0 * 3.0, chord_back = 2.0 * 3.0;
    s.spheres.push_back(sphere({0, 0, -5}, 3.0, std::log(2.0) / chord_back, {0.0, 1.0, 0.0}));   // green, behind
    s.spheres.push_back(sphere({0, 0, 1.5}, 3.0, std::log(2.0) / chord_front, {1.0, 0.0, 0.0})); // red, in front
    ScreendoorMethod door(device(), 8);
    const Image img = door.render(s);
    const Image ref = render_reference(s);
    double red = 0, green = 0, ref_green = 0;
    for (int j = 0; j < 48; ++j)
        for (int i = 0; i < 64; ++i) {
            red += img.pixel(i, j)[0];
            green += img.pixel(i, j)[1];
            ref_green += ref.pixel(i, j)[1];
        }
    EXPECT_NEAR(green / ref_green, 1.0, 0.05) << "red " << red << " green " << green << " reference green " << ref_green;
}

TEST_F(Screendoor, MaskMovesWithTheParticle) {
    // Move a translucent sphere right by exactly one pixel's footprint at its depth: its mask moves
    // with it, so the new image is the old one shifted by a pixel (up to the sliver of perspective
    // change), far closer than the noise that a mask fixed to the screen would redraw.
    Scene a = small_scene(64, 48);
    a.lighting.background = {0, 0, 0};
    a.spheres.push_back(sphere({0, 0, 0}, 1.2, 0.6));
    const double footprint = 5.0 * 2.0 * std::tan(20.0 * M_PI / 180.0) / 48.0;
    Scene b = a;
    b.spheres[0].center.x += footprint;
    ScreendoorMethod door(device(), 2);
    const Image ia = door.render(a);
    const Image ib = door.render(b);
    const Image ref = render_reference(a);
    double shifted = 0.0, noise = 0.0;
    for (int j = 0; j < 48; ++j)
        for (int i = 0; i + 1 < 64; ++i)
            for (int c = 0; c < 3; ++c) {
                shifted += std::abs(ib.pixel(i + 1, j)[c] - ia.pixel(i, j)[c]);
                noise += std::abs(ia.pixel(i, j)[c] - ref.pixel(i, j)[c]);
            }
    EXPECT_GT(noise, 0.0);
    EXPECT_LT(shifted, 0.1 * noise) << "shifted " << shifted << ", noise " << noise;
}

TEST_F(Screendoor, SettingIsSamplesPerAxis) {
    // The catalogued settings' names: test_gpu_methods.cpp.
    EXPECT_EQ(make_screendoor_method(device(), "1")->name(), "screendoor:1");
    EXPECT_EQ(make_screendoor_method(device(), "8")->name(), "screendoor:8");
    for (const char* bad : {"0", "9", "-1", "x", "4x", "2.5", " 4", "100"})
        EXPECT_THROW(make_screendoor_method(device(), bad), std::invalid_argument) << bad;
}

TEST_F(Screendoor, SupersampledSizeBeyondTheDeviceLimitIsRefused) {
    // lavapipe's largest image and framebuffer are 16384 wide: 8 x 2100 does not fit.
    Scene s = small_scene(2100, 4);
    s.spheres.push_back(sphere({0, 0, 0}, 1.0, 1.0));
    ScreendoorMethod door(device(), 8);
    EXPECT_THROW(door.render(s), std::runtime_error);
    ScreendoorMethod fits(device(), 7);  // 14700 wide
    EXPECT_NO_THROW(fits.render(s));
}

}  // namespace
}  // namespace brume
