// compare_images on images whose differences are known by construction.
#include "render/image_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace brume {
namespace {

// 4x3, channel values 0.1 .. 3.6 in steps of 0.1: peak 3.6.
Image ramp() {
    Image img(4, 3);
    for (std::size_t k = 0; k < img.rgb.size(); ++k) img.rgb[k] = 0.1f * float(k + 1);
    return img;
}

double peak_of(const Image& img) {
    double p = 0;
    for (const float v : img.rgb) p = std::max(p, double(v));
    return p;
}

TEST(ImageCompare, IdenticalImages) {
    const Image a = ramp();
    const ImageDiff d = compare_images(a, a, 0.0);
    EXPECT_DOUBLE_EQ(d.peak, peak_of(a));
    EXPECT_EQ(d.max_abs, 0.0);
    EXPECT_EQ(d.rmse, 0.0);
    EXPECT_TRUE(std::isinf(d.psnr_db) && d.psnr_db > 0);
    EXPECT_EQ(d.max_excess, 0.0);
    EXPECT_EQ(d.pixels_over, 0u);

    const ImageDiff loose = compare_images(a, a, 1e-3);
    EXPECT_DOUBLE_EQ(loose.max_excess, -1e-3) << "the margin left, as a fraction of peak";
}

TEST(ImageCompare, KnownDifferences) {
    const Image ref = ramp();
    Image test = ref;
    test.pixel(2, 1)[1] += 0.5f;  // the large one
    test.pixel(0, 2)[2] -= 0.1f;  // a small one
    const double peak = peak_of(ref);
    const double big = std::abs(double(test.pixel(2, 1)[1]) - double(ref.pixel(2, 1)[1]));
    const double small = std::abs(double(test.pixel(0, 2)[2]) - double(ref.pixel(0, 2)[2]));

    const double rel = 0.2 / peak;  // allows 0.2: the small one passes, the large one does not
    const ImageDiff d = compare_images(test, ref, rel);
    EXPECT_DOUBLE_EQ(d.peak, peak);
    EXPECT_DOUBLE_EQ(d.max_abs, big);
    EXPECT_NEAR(d.rmse, std::sqrt((big * big + small * small) / 36.0), 1e-15);
    EXPECT_NEAR(d.psnr_db, 20.0 * std::log10(peak / d.rmse), 1e-12);
    EXPECT_EQ(d.pixels_over, 1u);
    EXPECT_EQ(d.worst_i, 2);
    EXPECT_EQ(d.worst_j, 1);
    EXPECT_NEAR(d.max_excess, (big - 0.2) / peak, 1e-12);

    const ImageDiff strict = compare_images(test, ref, 0.0);
    EXPECT_EQ(strict.pixels_over, 2u);
    EXPECT_NEAR(strict.max_excess, big / peak, 1e-12);

    const ImageDiff lax = compare_images(test, ref, 1.0 / peak);
    EXPECT_EQ(lax.pixels_over, 0u);
    EXPECT_LT(lax.max_excess, 0.0);

    // Two channels of one pixel over count as one pixel.
    test.pixel(2, 1)[0] += 0.5f;
    EXPECT_EQ(compare_images(test, ref, rel).pixels_over, 1u);
}

TEST(ImageCompare, ToleranceImageWidensOnlyItsChannel) {
    const Image ref = ramp();
    Image test = ref;
    test.pixel(3, 0)[0] += 0.25f;
    Image tol(4, 3);
    tol.pixel(3, 0)[0] = 0.3f;
    const ImageDiff covered = compare_images(test, ref, 0.0, &tol);
    EXPECT_EQ(covered.pixels_over, 0u);
    EXPECT_EQ(covered.max_excess, 0.0) << "the unchanged channels, allowed nothing, sit exactly at the limit";
    const ImageDiff margin = compare_images(test, ref, 0.1 / peak_of(ref), &tol);
    EXPECT_NEAR(margin.max_excess, -0.1 / peak_of(ref), 1e-12) << "the covered channel has more room than that";

    Image wrong_channel(4, 3);
    wrong_channel.pixel(3, 0)[1] = 0.3f;
    const ImageDiff uncovered = compare_images(test, ref, 0.0, &wrong_channel);
    EXPECT_EQ(uncovered.pixels_over, 1u);
    EXPECT_GT(uncovered.max_excess, 0.0);
    EXPECT_EQ(uncovered.worst_i, 3);
    EXPECT_EQ(uncovered.worst_j, 0);

    // The relative and the per-pixel allowances add.
    const double peak = peak_of(ref);
    Image part(4, 3);
    part.pixel(3, 0)[0] = 0.2f;
    EXPECT_EQ(compare_images(test, ref, 0.1 / peak, &part).pixels_over, 0u);
    EXPECT_EQ(compare_images(test, ref, 0.0, &part).pixels_over, 1u);
}

TEST(ImageCompare, NanAndInfAreAlwaysOver) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Image ref = ramp();

    Image test = ref;
    test.pixel(1, 2)[2] = nan;
    Image huge(4, 3);
    for (float& v : huge.rgb) v = 1e30f;
    const ImageDiff d = compare_images(test, ref, 1e9, &huge);  // no allowance admits a NaN
    EXPECT_EQ(d.pixels_over, 1u);
    EXPECT_TRUE(std::isinf(d.max_excess) && d.max_excess > 0);
    EXPECT_EQ(d.worst_i, 1);
    EXPECT_EQ(d.worst_j, 2);
    EXPECT_TRUE(std::isinf(d.max_abs));
    EXPECT_TRUE(std::isinf(d.rmse));

    Image bad_ref = ref;
    bad_ref.pixel(0, 1)[0] = nan;
    bad_ref.pixel(3, 2)[2] = inf;  // and Inf in the reference does not become the peak
    const ImageDiff r = compare_images(ref, bad_ref, 1e9);
    EXPECT_EQ(r.pixels_over, 2u);
    EXPECT_TRUE(std::isfinite(r.peak));
    EXPECT_DOUBLE_EQ(r.peak, double(ref.pixel(3, 2)[1]));  // the largest finite value left

    Image both = ref;
    both.pixel(2, 2)[1] = inf;
    Image both_ref = ref;
    both_ref.pixel(2, 2)[1] = inf;  // inf - inf is NaN: not a match
    EXPECT_EQ(compare_images(both, both_ref, 1e9).pixels_over, 1u);
}

TEST(ImageCompare, BlackReferenceNormalisesByOne) {
    const Image black(2, 2);
    Image test(2, 2);
    test.pixel(1, 1)[0] = 0.25f;
    const ImageDiff d = compare_images(test, black, 0.5);
    EXPECT_EQ(d.peak, 0.0);
    EXPECT_EQ(d.pixels_over, 1u) << "rel_tol of a zero peak allows nothing";
    EXPECT_DOUBLE_EQ(d.max_excess, 0.25);
    EXPECT_TRUE(std::isfinite(d.max_excess));
}

TEST(ImageCompare, SizeMismatchThrows) {
    const Image a(4, 3), b(3, 4), c(4, 4);
    EXPECT_THROW(compare_images(a, b, 0.0), std::invalid_argument);
    EXPECT_THROW(compare_images(a, c, 0.0), std::invalid_argument);
    EXPECT_THROW(compare_images(a, a, 0.0, &b), std::invalid_argument);
    Image broken(4, 3);
    broken.rgb.pop_back();
    EXPECT_THROW(compare_images(broken, a, 0.0), std::invalid_argument);
    EXPECT_NO_THROW(compare_images(a, a, 0.0, &a));
}

TEST(ImageCompare, DescribeNamesTheWorstPixel) {
    const Image ref = ramp();
    Image test = ref;
    test.pixel(2, 1)[1] += 0.5f;
    const std::string line = describe(compare_images(test, ref, 0.0));
    EXPECT_NE(line.find("(2, 1)"), std::string::npos) << line;
    EXPECT_NE(line.find("1 pixels over"), std::string::npos) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
}

}  // namespace
}  // namespace brume

namespace brume {
namespace {

TEST(TemporalError, ZeroWhenTheMethodChangesLikeTheReference) {
    Image r0(2, 1), r1(2, 1), m0(2, 1), m1(2, 1);
    r0.rgb = {0, 0, 0, 1, 1, 1};
    r1.rgb = {0.5f, 0.5f, 0.5f, 1, 1, 1};
    m0.rgb = {0.1f, 0.1f, 0.1f, 1, 1, 1};  // a constant offset from the reference: no popping
    m1.rgb = {0.6f, 0.6f, 0.6f, 1, 1, 1};
    EXPECT_NEAR(temporal_error(m1, m0, r1, r0), 0.0, 1e-7);
}

TEST(TemporalError, MeasuresAJumpTheReferenceDoesNotMake) {
    Image r(2, 1), m0(2, 1), m1(2, 1);
    r.rgb = {1, 1, 1, 1, 1, 1};  // the reference is still
    m0.rgb = {1, 1, 1, 1, 1, 1};
    m1.rgb = {1, 1, 1, 0.4f, 0.4f, 0.4f};  // one pixel of two pops by 0.6
    EXPECT_NEAR(temporal_error(m1, m0, r, r), 0.6 / 2.0, 1e-6);
    Image wrong(3, 1);
    EXPECT_THROW(temporal_error(wrong, m0, r, r), std::invalid_argument);
}

}  // namespace
}  // namespace brume
