// The preview's heat-map overlay (app/preview_heat_map.*): pixels without a list keep the frame
// bit for bit; a pixel with a list is the frame mixed with the ramp's colour, which after the
// exposure and the sRGB transfer the PNG writer applies is the ramp's sRGB colour (checked with the
// tint alone, over a black frame); the ramp runs from blue at 1 node to red at the longest list.
#include "app/preview_heat_map.h"

#include "render/image_io.h"

#include <gtest/gtest.h>

#include <cmath>

namespace brume::app {
namespace {

Image filled(int w, int h, float r, float g, float b) {
    Image image(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            image.pixel(i, j)[0] = r;
            image.pixel(i, j)[1] = g;
            image.pixel(i, j)[2] = b;
        }
    return image;
}

TEST(PreviewHeatMap, PixelsWithoutAListKeepTheFrame) {
    const Image frame = filled(4, 3, 0.3f, 0.2f, 0.1f);
    Image counts = filled(4, 3, 0.0f, 0.0f, 0.0f);
    counts.pixel(2, 1)[0] = 3.0f;
    const Image out = overlay_list_heat_map(frame, counts, 3.0, 0.0);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i)
            for (int c = 0; c < 3; ++c) {
                if (i == 2 && j == 1) continue;
                EXPECT_EQ(out.pixel(i, j)[c], frame.pixel(i, j)[c]);
            }
    bool changed = false;
    for (int c = 0; c < 3; ++c) changed = changed || out.pixel(2, 1)[c] != frame.pixel(2, 1)[c];
    EXPECT_TRUE(changed);
}

// Over a black frame the pixel is the tint alone: exposed and encoded, it is the ramp's colour times
// the opacity in linear light, whatever the exposure.
TEST(PreviewHeatMap, TintShowsTheRampColourAfterTheExposure) {
    for (double exposure : {-2.0, 0.0, 1.5}) {
        SCOPED_TRACE(exposure);
        const Image frame = filled(3, 1, 0.0f, 0.0f, 0.0f);
        Image counts = filled(3, 1, 0.0f, 0.0f, 0.0f);
        counts.pixel(0, 0)[0] = 1.0f;  // the shortest list: blue
        counts.pixel(1, 0)[0] = 5.0f;  // half way from 1 to 9: green
        counts.pixel(2, 0)[0] = 9.0f;  // the longest: red
        const Image out = overlay_list_heat_map(frame, counts, 9.0, exposure);
        const double ts[] = {0.0, 0.5, 1.0};
        for (int i = 0; i < 3; ++i) {
            const std::array<float, 3> want = heat_colour(ts[i]);
            for (int c = 0; c < 3; ++c) {
                const float shown = srgb_encode(float(out.pixel(i, 0)[c] * std::exp2(exposure) / kHeatMapOpacity));
                // The ramp is tabulated in 256 steps: within half a step, where it changes by at most
                // 0.9 over a quarter of its span (0.9 * 4 / 255 / 2 = 0.0071), plus float rounding.
                EXPECT_NEAR(shown, want[std::size_t(c)], 0.0075) << "pixel " << i << " channel " << c;
            }
        }
    }
    const std::array<float, 3> blue = heat_colour(0.0), red = heat_colour(1.0);
    EXPECT_GT(blue[2], blue[0]);
    EXPECT_GT(red[0], red[2]);
}

TEST(PreviewHeatMap, RefusesCountsOfAnotherSize) {
    EXPECT_THROW(overlay_list_heat_map(filled(4, 3, 0, 0, 0), filled(3, 3, 0, 0, 0), 1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace brume::app
