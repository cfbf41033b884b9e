// `sorted` (the painter's algorithm of "11.4 Transparency (and Alpha Blending)", a WebGL lesson): the insertion sort reusing last frame's order, on the CPU, and the planar
// billboards against the reference where back-to-front "over" is exact, and where it is not.
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/sorted.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace brume {
namespace {

using testing::compare_with_reference;
using testing::GpuTest;

// ---- the sort, on the CPU ----

bool is_back_to_front(const std::vector<std::uint32_t>& order, const std::vector<double>& depth) {
    for (std::size_t i = 1; i < order.size(); ++i)
        if (depth[order[i - 1]] < depth[order[i]]) return false;
    return true;
}

bool is_permutation_of_all(std::vector<std::uint32_t> order, std::size_t n) {
    if (order.size() != n) return false;
    std::sort(order.begin(), order.end());
    for (std::size_t i = 0; i < n; ++i)
        if (order[i] != i) return false;
    return true;
}

// Pairs out of back-to-front order: what an insertion sort must move.
std::uint64_t inversions(const std::vector<std::uint32_t>& order, const std::vector<double>& depth) {
    std::uint64_t count = 0;
    for (std::size_t i = 0; i < order.size(); ++i)
        for (std::size_t j = i + 1; j < order.size(); ++j)
            if (depth[order[i]] < depth[order[j]]) ++count;
    return count;
}

TEST(SortBackToFront, FromNothingSortsEverySphereFarthestFirst) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    std::vector<double> depth(300);
    for (double& d : depth) d = std::round(u(rng));  // many ties
    std::vector<std::uint32_t> order;
    const SortCounts c = sort_back_to_front(order, depth);
    EXPECT_TRUE(c.full_sort);  // about n^2 / 4 inversions: past the insertion sort's budget
    EXPECT_TRUE(is_permutation_of_all(order, depth.size()));
    EXPECT_TRUE(is_back_to_front(order, depth));
    // The same as a stable sort of the indices by decreasing depth.
    std::vector<std::uint32_t> expected(depth.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(), [&](auto a, auto b) { return depth[a] > depth[b]; });
    EXPECT_EQ(order, expected);
}

TEST(SortBackToFront, CoherentFramesCostOneComparisonPerSpherePlusOnePerInversion) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(0.0, 100.0), jitter(-0.3, 0.3);
    std::vector<double> depth(1000);
    for (double& d : depth) d = u(rng);
    std::vector<std::uint32_t> order;
    const SortCounts first = sort_back_to_front(order, depth);
    EXPECT_TRUE(first.full_sort);  // from index order: about n^2 / 4 inversions
    EXPECT_LE(first.moves, 32u * depth.size() + 1024 + depth.size());  // gave up early, not O(n^2)

    for (int frame = 0; frame < 5; ++frame) {
        for (double& d : depth) d += jitter(rng);  // particles move a little
        const std::uint64_t expected_moves = inversions(order, depth);
        const SortCounts c = sort_back_to_front(order, depth);
        EXPECT_TRUE(is_back_to_front(order, depth));
        EXPECT_FALSE(c.full_sort);
        EXPECT_EQ(c.moves, expected_moves);
        EXPECT_LE(c.comparisons, depth.size() - 1 + c.moves);
        EXPECT_LT(c.moves, 20000u);  // far fewer than sorting from scratch
    }
    // Nothing moved: one comparison per neighbouring pair, no moves.
    const SortCounts still = sort_back_to_front(order, depth);
    EXPECT_EQ(still.moves, 0u);
    EXPECT_EQ(still.comparisons, depth.size() - 1);
}

TEST(SortBackToFront, EqualDepthsKeepLastFramesOrder) {
    std::vector<std::uint32_t> order = {3, 1, 4, 0, 2};
    const std::vector<double> depth(5, 1.5);
    const SortCounts c = sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{3, 1, 4, 0, 2}));
    EXPECT_EQ(c.moves, 0u);
}

TEST(SortBackToFront, FallbackForAFarOffOrderKeepsTiesInLastFramesOrder) {
    std::vector<std::uint32_t> order(500);
    std::iota(order.rbegin(), order.rend(), 0u);  // last frame: 499, 498, ..., 0
    std::vector<double> depth(500);
    for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = double(i % 3);
    std::vector<std::uint32_t> expected = order;
    std::stable_sort(expected.begin(), expected.end(), [&](auto a, auto b) { return depth[a] > depth[b]; });
    const SortCounts c = sort_back_to_front(order, depth);
    EXPECT_TRUE(c.full_sort);
    EXPECT_EQ(order, expected);
}

TEST(SortBackToFront, AddedSpheresAreSortedIn) {
    std::vector<double> depth = {5, 1, 3, 2, 4};
    std::vector<std::uint32_t> order;
    sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{0, 4, 2, 3, 1}));
    depth.push_back(6);    // 5: farthest
    depth.push_back(0.5);  // 6: nearest
    depth.push_back(2.5);  // 7: between 3 (2.0) and 2 (3.0)
    sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{5, 0, 4, 2, 7, 3, 1, 6}));
}

TEST(SortBackToFront, RemovedSpheresLeaveAndTheRestKeepTheirOrder) {
    std::vector<double> depth = {1, 1, 1, 1, 1, 1};
    std::vector<std::uint32_t> order = {5, 2, 0, 4, 3, 1};  // last frame's order (all ties)
    depth.resize(3);                                        // spheres 3, 4, 5 are gone
    sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{2, 0, 1}));
    depth = {1, 3, 2};
    sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{1, 2, 0}));
    depth.clear();
    sort_back_to_front(order, depth);
    EXPECT_TRUE(order.empty());
}

TEST(SortBackToFront, RepairsAnOrderThatIsNotAPermutation) {
    std::vector<std::uint32_t> order = {2, 2, 9, 0, 7, 0};
    const std::vector<double> depth = {3, 2, 1, 0};
    sort_back_to_front(order, depth);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

TEST(SortBackToFront, ViewDepthIsTheCentreAlongTheViewDirection) {
    Scene s;
    s.camera.position = {0, 0, 5};
    s.camera.look_at = {0, 0, 0};
    Sphere a, b, c;
    a.center = {0, 0, 0};
    b.center = {3, -2, 1};   // off axis: only the component along the view counts
    c.center = {0, 0, 7};    // behind the eye
    s.spheres = {a, b, c};
    const std::vector<double> d = view_depths(s);
    ASSERT_EQ(d.size(), 3u);
    EXPECT_DOUBLE_EQ(d[0], 5.0);
    EXPECT_DOUBLE_EQ(d[1], 4.0);
    EXPECT_DOUBLE_EQ(d[2], -2.0);
}

// ---- the method, on lavapipe ----

// min_transmittance 0: back-to-front compositing integrates everything.
Scene small_scene(int w = 128, int h = 96) { return testing::small_scene(w, h); }

using testing::add_back_wall;
using testing::sphere;

class Sorted : public GpuTest {};

TEST_F(Sorted, SingleSphereMatchesReference) {
    // Wholly in front of the wall and of the eye: the billboard's chord is the exact one, one sphere
    // has no order to get wrong.
    Scene s = small_scene();
    add_back_wall(s);
    s.spheres.push_back(sphere({0.3, -0.2, 0.0}, 1.1, 1.3));
    SortedMethod sorted(device());
    FrameStats stats;
    const Image img = sorted.render(s, &stats);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    ASSERT_EQ(stats.passes.size(), 3u);
}

TEST_F(Sorted, NonIntersectingStackedSpheresMatchReference) {
    const Scene s = testing::stacked_scene();
    SortedMethod sorted(device());
    const Image img = sorted.render(s);
    EXPECT_EQ(sorted.order(), (std::vector<std::uint32_t>{0, 3, 2, 4, 1}));
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
}

// testing::circling_spheres before the back wall: every frame has an exact answer.
Scene circling_frame(int frame) {
    Scene s = small_scene();
    add_back_wall(s);
    s.spheres = testing::circling_spheres(frame);
    return s;
}

TEST_F(Sorted, OrderStaysRightAcrossFramesAsSpheresMoveAppearAndLeave) {
    SortedMethod sorted(device());
    for (int frame = 0; frame < 7; ++frame) {
        const Scene s = circling_frame(frame);
        const Image img = sorted.render(s);
        const std::vector<double> depth = view_depths(s);
        EXPECT_TRUE(is_permutation_of_all(sorted.order(), s.spheres.size())) << "frame " << frame;
        EXPECT_TRUE(is_back_to_front(sorted.order(), depth)) << "frame " << frame;
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << "frame " << frame << ": " << describe(d);
    }
    // The last frame repeats the first: the sort restored the first frame's order.
    EXPECT_EQ(sorted.order(), (std::vector<std::uint32_t>{2, 0, 1}));
}

TEST_F(Sorted, IntersectingSpheresDisagreeWithReference) {
    // The failure mode this method is charted for: "over" of two separately attenuated spheres is not
    // the integral through two intersecting media.
    const Scene s = testing::intersecting_pair(0.35, 2.0, 0.0, 0.1);
    SortedMethod sorted(device());
    const Image img = sorted.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_GT(d.max_excess, 0.05) << describe(d);
    EXPECT_GT(d.pixels_over, 500u) << describe(d);
}

TEST_F(Sorted, PopsWhenTwoParticlesOrderFlips) {
    // Two intersecting spheres at almost the same depth; a 2 mm step of one flips their order. The
    // reference barely changes, the sorted image jumps (the popping metric, temporal_error in
    // render/image_compare.h).
    SortedMethod sorted(device());
    const testing::OrderFlip f = testing::flip_order(sorted);
    EXPECT_LT(f.reference_step, 1e-3);
    EXPECT_GT(f.popping, 0.02);
    EXPECT_GT(f.popping, 30.0 * f.reference_step) << "popping " << f.popping << ", reference step " << f.reference_step;
    const ImageDiff sorted_step = compare_images(f.after, f.before, 0.0);
    EXPECT_GT(sorted_step.max_abs, 0.3 * sorted_step.peak) << describe(sorted_step);
}

TEST_F(Sorted, BillboardIsCutHardWhereItsPlaneMeetsGeometry) {
    // A wall at z in [-0.4, 0.2] through a sphere centred at z = -0.3: the billboard's plane lies inside
    // the wall, so nothing of the sphere shows, though its front part pokes out of the wall.
    Scene s = small_scene(64, 48);
    s.boxes.push_back(Box{{-3, -3, -0.4}, {3, 3, 0.2}, {0.02, 0.05, 0.03}});
    s.spheres.push_back(sphere({0, 0, -0.3}, 1.0, 1.5));
    SortedMethod sorted(device());
    const Image img = sorted.render(s);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.pixel(32, 24)[c], float(s.boxes[0].radiance[c]));
    const Image ref = render_reference(s);
    EXPECT_GT(std::abs(ref.pixel(32, 24)[0] - img.pixel(32, 24)[0]), 0.05);  // the reference sees the front part

    // With the centre in front of the wall, the whole chord shows, even the part inside the wall.
    s.spheres[0].center.z = 0.5;
    const Image whole = sorted.render(s);
    const ImageDiff d = compare_with_reference(whole, s);
    EXPECT_GT(d.max_excess, 0.05) << describe(d);
}

TEST_F(Sorted, BillboardBehindTheEyeIsDropped) {
    // The eye is inside a sphere whose centre is behind it: the billboard's plane is behind the eye,
    // so the sphere vanishes although the eye sits in its medium.
    Scene s = small_scene(64, 48);
    add_back_wall(s);
    s.spheres.push_back(sphere({0, 0, 5.3}, 1.0, 1.0));
    SortedMethod sorted(device());
    const Image img = sorted.render(s);
    Scene empty = s;
    empty.spheres.clear();
    const ImageDiff none = compare_images(img, render_reference(empty), 1e-6);
    EXPECT_EQ(none.pixels_over, 0u) << describe(none);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_GT(d.max_excess, 0.05) << describe(d);
}

TEST_F(Sorted, EmptySceneLeavesNothingToSort) {
    // (That it shows the opaque image: test_gpu_methods.cpp.)
    Scene s = small_scene(40, 30);
    s.boxes.push_back(Box{{-1, -1, -1}, {1, 0.5, 1}, {0.7, 0.2, 0.1}});
    SortedMethod sorted(device());
    sorted.render(testing::stacked_scene(40, 30));  // an order to forget
    sorted.render(s);
    EXPECT_TRUE(sorted.order().empty());
}

TEST_F(Sorted, FactoryTakesNoSetting) {
    // Called directly, not through the registry (which refuses "sorted:4" first); the name and
    // exactness: test_gpu_methods.cpp.
    EXPECT_THROW(make_sorted_method(device(), "4"), std::invalid_argument);
}

}  // namespace
}  // namespace brume
