// peel (classic and dual depth peeling) against the CPU reference and closed forms.
// Front-to-back "under" compositing of whole spheres is exact when the spheres' chords do not
// overlap, so on such scenes peel must match the reference as ppll does; elsewhere the tests check
// the stated approximations (the tail slab, coincident spheres composited one by one).
#include "test_scenes.h"
#include "gpu_test_env.h"
#include "render/methods/peel.h"
#include "render/methods/ppll.h"
#include "sim/camera_rays.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace brume {
namespace {

using testing::all_finite;
using testing::compare_with_reference;
using testing::GpuTest;

// The shared small scene, from farther away: (0, 0, 8).
Scene small_scene(int w = 96, int h = 72) {
    Scene s = testing::small_scene(w, h);
    s.camera.position = {0.0, 0.0, 8.0};
    return s;
}

using testing::sphere;

PeelOptions classic(int n) {
    PeelOptions o;
    o.passes = n;
    return o;
}
PeelOptions dual(int n) {
    PeelOptions o;
    o.passes = n;
    o.dual = true;
    return o;
}

// K equal spheres centred on the view axis one behind another, 1.5 apart (radius 0.6: disjoint).
// Seen from the eye each disc lies inside the disc of every sphere in front of it, so a pixel that
// meets sphere k meets spheres 0..k-1 first: "the first n layers" is the same n spheres everywhere.
Scene nested_scene(int count, const std::vector<glm::dvec3>& albedos, const std::vector<double>& taus) {
    Scene s = small_scene();
    for (int k = 0; k < count; ++k)
        s.spheres.push_back(sphere({0.0, 0.0, 3.0 - 1.5 * k}, 0.6, taus[k % taus.size()], albedos[k % albedos.size()]));
    return s;
}

// Disjoint spheres (gap >= 0.02) at random in a box, some cut by opaque boxes.
Scene disjoint_scene(int count, unsigned seed, bool with_boxes) {
    Scene s = testing::random_scene(128, 96, 0, seed, with_boxes);  // its view and boxes
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int attempts = 0;
    while (int(s.spheres.size()) < count && ++attempts < 100000) {
        Sphere c = sphere({u(rng) * 4 - 2, u(rng) * 3 - 1, u(rng) * 6 - 4}, 0.15 + 0.35 * u(rng),
                          std::pow(10.0, u(rng) * 2.5 - 1.5), {u(rng), u(rng), u(rng)});
        bool clear = true;
        for (const Sphere& o : s.spheres)
            clear = clear && glm::length(o.center - c.center) > o.radius + c.radius + 0.02;
        if (clear) s.spheres.push_back(c);
    }
    return s;
}

// Per pixel, the spheres the ray meets in front of the opaque surface, sorted by entry (double).
struct Hit {
    double t0, t1;
    int sphere;
};
std::vector<Hit> pixel_hits(const Scene& s, const CameraRays& rays, int i, int j, glm::dvec3* ls = nullptr,
                            glm::dvec3* behind = nullptr) {
    const glm::dvec3 d = rays.pixel_direction(i, j);
    const testing::OpaqueHit opaque = testing::opaque_hit(s, rays.eye, d);
    if (behind) *behind = opaque.radiance;
    std::vector<Hit> hits;
    for (int k = 0; k < int(s.spheres.size()); ++k)
        if (const auto c = testing::chord(rays.eye, d, s.spheres[k], opaque.t)) hits.push_back({c->t0, c->t1, k});
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t0 < b.t0; });
    if (ls) *ls = testing::source_radiance(s, d);
    return hits;
}

std::size_t max_layers(const Scene& s) {
    const CameraRays rays = make_camera_rays(s.camera);
    std::size_t m = 0;
    for (int j = 0; j < s.camera.height; ++j)
        for (int i = 0; i < s.camera.width; ++i) m = std::max(m, pixel_hits(s, rays, i, j).size());
    return m;
}

class Peel : public GpuTest {};

TEST_F(Peel, SettingsParseAndName) {
    // The catalogued settings' names: test_gpu_methods.cpp.
    EXPECT_EQ(make_peel_method(device(), "dual:16")->name(), "peel:dual:16");
    EXPECT_FALSE(make_peel_method(device(), "2")->exact());
    // "dual" alone rendered peel:dual:8 unasked: peel:dual:N names its N.
    for (const char* bad : {"0", "65", "x", "dual", "dual:", "dual:0", "-3", "4k", "dual:100"})
        EXPECT_THROW(parse_peel_setting(bad), std::invalid_argument) << bad;
    EXPECT_THROW(PeelMethod(device(), classic(0)), std::invalid_argument);
    EXPECT_THROW(PeelMethod(device(), dual(65)), std::invalid_argument);
}

TEST_F(Peel, SingleSphereMatchesReferenceAndClosedForm) {
    Scene s = small_scene(65, 65);  // odd: the centre pixel's ray goes through the sphere centre
    s.spheres.push_back(sphere({0, 0, 0}, 1.0, 0.7));
    const glm::dvec3 centre = testing::single_sphere_radiance(s, 32, 32);
    for (const PeelOptions& o : {classic(8), dual(8)}) {
        PeelMethod peel(device(), o);
        const Image img = peel.render(s);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.pixel(32, 32)[c], centre[c], 1e-6) << peel.name() << " channel " << c;
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.pixel(0, 0)[c], float(s.lighting.background[c])) << peel.name();
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << peel.name() << ": " << describe(d);
    }
}

TEST_F(Peel, SpheresOneBehindAnotherMatchReferenceUpToThePassCount) {
    const std::vector<glm::dvec3> albedos = {{0.9, 0.2, 0.2}, {0.2, 0.9, 0.3}, {0.2, 0.3, 0.95}, {0.9, 0.9, 0.2}};
    const Scene s = nested_scene(6, albedos, {0.8, 1.5, 0.4, 2.0, 0.3});
    ASSERT_EQ(max_layers(s), 6u);
    for (const PeelOptions& o : {classic(6), classic(8), classic(64), dual(3), dual(8)}) {
        PeelMethod peel(device(), o);
        const Image img = peel.render(s);
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << peel.name() << ": " << describe(d);
        EXPECT_TRUE(all_finite(img));
    }
}

TEST_F(Peel, DisjointRandomSpheresWithBoxesMatchReference) {
    Scene s = disjoint_scene(80, 11, true);
    s.render.min_transmittance = 1e-4;  // exercised: some spheres are thick enough to stop a pixel
    const std::size_t depth = max_layers(s);
    ASSERT_GE(depth, 6u);
    ASSERT_LE(depth, 64u);
    PeelMethod peel(device(), classic(int(depth)));
    const Image img = peel.render(s);
    const ImageDiff d = compare_with_reference(img, s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_TRUE(all_finite(img));
}

TEST_F(Peel, DualEqualsClassicOnDisjointScenes) {
    const Scene s = disjoint_scene(80, 5, true);
    const std::size_t depth = max_layers(s);
    ASSERT_GE(depth, 6u);
    PeelMethod classic_peel(device(), classic(int(depth)));
    PeelMethod dual_peel(device(), dual(int(depth + 1) / 2));
    const Image a = classic_peel.render(s), b = dual_peel.render(s);
    const ImageDiff vs_classic = compare_images(b, a, 1e-5);
    EXPECT_EQ(vs_classic.pixels_over, 0u) << describe(vs_classic);
    const ImageDiff vs_ref = compare_with_reference(b, s);
    EXPECT_EQ(vs_ref.pixels_over, 0u) << describe(vs_ref);
    // Half the passes, each peeling a front and a back layer.
    EXPECT_LE(dual_peel.last_frame().passes_drawn, int(depth + 1) / 2 + 1);
}

TEST_F(Peel, LayersBeyondThePassesAreDroppedOrApproximatedAsStated) {
    // Six nested spheres, two passes: the first two spheres are peeled exactly everywhere.
    const std::vector<glm::dvec3> grey = {{0.8, 0.8, 0.8}};
    const std::vector<glm::dvec3> mixed = {{0.9, 0.3, 0.2}, {0.3, 0.8, 0.3}, {0.7, 0.7, 0.7},
                                           {0.95, 0.95, 0.95}, {0.2, 0.2, 0.9}, {0.5, 0.9, 0.9}};
    const std::vector<double> taus = {0.6, 0.9, 0.5, 1.2, 0.7, 0.4};

    // Without the tail the result is exactly the scene of the first two spheres.
    {
        const Scene s = nested_scene(6, mixed, taus);
        Scene front = s;
        front.spheres.resize(2);
        PeelOptions o = classic(2);
        o.tail = false;
        PeelMethod peel(device(), o);
        const Image img = peel.render(s);
        const ImageDiff d = compare_with_reference(img, front);
        EXPECT_EQ(d.pixels_over, 0u) << describe(d);
        EXPECT_GT(compare_with_reference(img, s).pixels_over, 0u);  // and so not the whole scene
        // dual:2 peels two front and two back layers: where a pixel meets all six spheres the middle
        // two are dropped; where it meets at most four, nothing is.
        o.dual = true;
        PeelMethod dual_peel(device(), o);
        const Image dimg = dual_peel.render(s);
        Scene ends = s;
        ends.spheres.erase(ends.spheres.begin() + 2, ends.spheres.begin() + 4);
        const Image ref_all = render_reference(s), ref_ends = render_reference(ends);
        const CameraRays rays = make_camera_rays(s.camera);
        int six = 0, bad = 0;
        for (int j = 0; j < s.camera.height; ++j)
            for (int i = 0; i < s.camera.width; ++i) {
                const std::size_t n = pixel_hits(s, rays, i, j).size();
                if (n == 5) continue;
                const Image& want = n == 6 ? ref_ends : ref_all;
                six += n == 6;
                for (int c = 0; c < 3; ++c) bad += std::abs(dimg.pixel(i, j)[c] - want.pixel(i, j)[c]) > 1e-5;
            }
        EXPECT_GT(six, 20);
        EXPECT_EQ(bad, 0);
    }
    // With the tail, a tail of one colour is exact: its transmittance is exp(-sum x) either way.
    for (const PeelOptions& o : {classic(2), dual(1)}) {
        Scene s = nested_scene(6, grey, taus);
        s.spheres[0].albedo = {0.9, 0.2, 0.2};
        s.spheres[5].albedo = {0.8, 0.8, 0.8};
        PeelMethod peel(device(), o);
        const Image img = peel.render(s);
        const ImageDiff d = compare_with_reference(img, s);
        EXPECT_EQ(d.pixels_over, 0u) << peel.name() << ": " << describe(d);
        EXPECT_TRUE(peel.last_frame().tail_drawn);
    }
    // A tail of many colours: per channel |error| <= T_front * (1 - exp(-X)) * (max - min colour).
    {
        const Scene s = nested_scene(6, mixed, taus);
        PeelMethod peel(device(), classic(2));
        const Image img = peel.render(s);
        const Image ref = render_reference(s);
        const Image tol = reference_tolerance(s, testing::kRayRelError);
        const CameraRays rays = make_camera_rays(s.camera);
        double worst_error = 0.0, worst_ratio = 0.0;
        int over = 0;
        for (int j = 0; j < s.camera.height; ++j)
            for (int i = 0; i < s.camera.width; ++i) {
                glm::dvec3 ls;
                const std::vector<Hit> hits = pixel_hits(s, rays, i, j, &ls);
                double t_front = 1.0, x_tail = 0.0;
                glm::dvec3 lo(INFINITY), hi(-INFINITY);
                for (std::size_t k = 0; k < hits.size(); ++k) {
                    const Sphere& sp = s.spheres[hits[k].sphere];
                    const double x = sp.extinction * (hits[k].t1 - hits[k].t0);
                    if (k < 2) {
                        t_front *= std::exp(-x);
                    } else {
                        x_tail += x;
                        lo = glm::min(lo, sp.albedo * ls);
                        hi = glm::max(hi, sp.albedo * ls);
                    }
                }
                for (int c = 0; c < 3; ++c) {
                    const double bound = x_tail > 0 ? t_front * -std::expm1(-x_tail) * (hi[c] - lo[c]) : 0.0;
                    const double error = std::abs(double(img.pixel(i, j)[c]) - ref.pixel(i, j)[c]);
                    const double slack = 1e-5 + 2.0 * tol.pixel(i, j)[c];
                    if (error > bound + slack) ++over;
                    worst_error = std::max(worst_error, error);
                    if (bound > 1e-3) worst_ratio = std::max(worst_ratio, error / bound);
                }
            }
        EXPECT_EQ(over, 0);
        EXPECT_GT(worst_error, 1e-3);  // the approximation is visible: the bound is not vacuous
        EXPECT_GT(worst_ratio, 0.05);
        // Dropping the tail instead breaks the bound: the colour of the tail matters.
        PeelOptions drop = classic(2);
        drop.tail = false;
        PeelMethod dropped(device(), drop);
        const Image img_drop = dropped.render(s);
        double drop_error = 0.0;
        for (std::size_t k = 0; k < img_drop.rgb.size(); ++k)
            drop_error = std::max(drop_error, std::abs(double(img_drop.rgb[k]) - ref.rgb[k]));
        EXPECT_GT(drop_error, 2.0 * worst_error);
    }
}

TEST_F(Peel, CoincidentSpheresArePeeledOneByOne) {
    // Three spheres with one centre and radius: equal entry distances everywhere. With one colour
    // the sequence of layers composites to the reference's mixture exactly (same total optical depth).
    Scene s = small_scene(65, 65);
    for (double tau : {0.3, 0.5, 0.8}) s.spheres.push_back(sphere({0, 0, 0}, 1.0, tau, {0.7, 0.6, 0.5}));
    s.spheres.push_back(sphere({0, 0, -3}, 0.8, 1.0, {0.2, 0.4, 0.9}));  // one more layer behind
    PeelMethod peel(device(), classic(8));
    const ImageDiff d = compare_with_reference(peel.render(s), s);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_EQ(peel.last_frame().passes_drawn, 5);  // four layers one by one, then an empty pass
    PeelMethod dual_peel(device(), dual(8));
    const ImageDiff dd = compare_with_reference(dual_peel.render(s), s);
    EXPECT_EQ(dd.pixels_over, 0u) << describe(dd);

    // Different colours: the group is composited in sphere-index order, one layer at a time.
    s.spheres[0].albedo = {0.9, 0.1, 0.1};
    s.spheres[1].albedo = {0.1, 0.9, 0.1};
    s.spheres[2].albedo = {0.1, 0.1, 0.9};
    const Image a = peel.render(s), b = dual_peel.render(s);
    const CameraRays rays = make_camera_rays(s.camera);
    glm::dvec3 ls;
    const std::vector<Hit> hits = pixel_hits(s, rays, 32, 32, &ls);
    ASSERT_EQ(hits.size(), 4u);
    glm::dvec3 expected(0.0);
    double t = 1.0;
    for (int k : {0, 1, 2, 3}) {  // sphere index order within the group, then the sphere behind
        const int sphere_index = k;
        const Sphere& sp = s.spheres[sphere_index];
        const Hit& h = *std::find_if(hits.begin(), hits.end(), [&](const Hit& x) { return x.sphere == sphere_index; });
        const double e = std::exp(-sp.extinction * (h.t1 - h.t0));
        expected += t * (1.0 - e) * sp.albedo * ls;
        t *= e;
    }
    expected += t * s.lighting.background;
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(a.pixel(32, 32)[c], expected[c], 2e-6) << "classic channel " << c;
        EXPECT_NEAR(b.pixel(32, 32)[c], expected[c], 2e-6) << "dual channel " << c;
    }
    const ImageDiff ab = compare_images(b, a, 1e-5);
    EXPECT_EQ(ab.pixels_over, 0u) << describe(ab);
}

TEST_F(Peel, EarlyStopUsesFewerPassesOnShallowScenes) {
    const std::vector<glm::dvec3> albedos = {{0.8, 0.8, 0.8}};
    for (int layers : {1, 3, 5}) {
        const Scene s = nested_scene(layers, albedos, {0.5});
        PeelMethod peel(device(), classic(16));
        FrameStats stats;
        peel.render(s, &stats);
        const PeelFrameInfo& info = peel.last_frame();
        EXPECT_EQ(info.passes_drawn, layers + 1) << layers;  // the last pass finds nothing
        EXPECT_LT(info.passes_recorded, 16) << layers;       // the CPU stopped submitting
        EXPECT_FALSE(info.tail_drawn);
        const auto peels = std::count_if(stats.passes.begin(), stats.passes.end(),
                                         [](const PassTime& p) { return p.name.rfind("peel[", 0) == 0; });
        EXPECT_EQ(peels, layers + 1);
        EXPECT_GT(info.pixels_going_on[0], 0u);
        EXPECT_EQ(info.pixels_going_on[std::size_t(layers)], 0u);

        PeelMethod dual_peel(device(), dual(16));
        dual_peel.render(s);
        // The window pass, then ceil(layers / 2) passes; the dual window knows when it is empty.
        EXPECT_EQ(dual_peel.last_frame().passes_drawn, 1 + (layers + 1) / 2) << layers;
    }
    // A scene deeper than the passes uses them all and then the tail.
    const Scene deep = nested_scene(6, albedos, {0.5});
    PeelMethod peel(device(), classic(4));
    peel.render(deep);
    EXPECT_EQ(peel.last_frame().passes_drawn, 4);
    EXPECT_TRUE(peel.last_frame().tail_drawn);
    // Opaque-enough layers stop the pixel as the reference does, and with it the peeling.
    Scene thick = nested_scene(6, albedos, {20.0});
    thick.render.min_transmittance = 1e-4;
    PeelMethod stop(device(), classic(8));
    const ImageDiff d = compare_with_reference(stop.render(thick), thick);
    EXPECT_EQ(d.pixels_over, 0u) << describe(d);
    EXPECT_LT(stop.last_frame().passes_drawn, 6);
}

// What peeling computes when media intersect: each sphere's whole clipped chord composited as one
// layer, in order of (entry distance, sphere index), with the reference's early termination. Double.
Image layer_model(const Scene& s) {
    const CameraRays rays = make_camera_rays(s.camera);
    Image img(s.camera.width, s.camera.height);
    for (int j = 0; j < s.camera.height; ++j)
        for (int i = 0; i < s.camera.width; ++i) {
            glm::dvec3 ls, behind;
            std::vector<Hit> hits = pixel_hits(s, rays, i, j, &ls, &behind);
            std::stable_sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                return a.t0 < b.t0 || (a.t0 == b.t0 && a.sphere < b.sphere);
            });
            glm::dvec3 l(0.0);
            double t = 1.0;
            for (const Hit& h : hits) {
                const Sphere& sp = s.spheres[h.sphere];
                const double x = sp.extinction * (h.t1 - h.t0);
                l += t * -std::expm1(-x) * sp.albedo * ls;
                t *= std::exp(-x);
                if (t < s.render.min_transmittance) {
                    t = 0.0;
                    break;
                }
            }
            l += t * behind;
            for (int c = 0; c < 3; ++c) img.rgb[(std::size_t(j) * s.camera.width + i) * 3 + c] = float(l[c]);
        }
    return img;
}

TEST_F(Peel, OverlappingSpheresCompositeWholeSpheresInEntryOrder) {
    // Not the reference (intersecting media are not mixed), but exactly the layer model above.
    Scene s = testing::random_scene(128, 96, 200, 3, true);
    const Image tol = reference_tolerance(s, testing::kRayRelError);
    for (double min_t : {0.0, 1e-3}) {
        s.render.min_transmittance = min_t;
        const Image model = layer_model(s);
        const Image ref = render_reference(s);
        const std::size_t depth = max_layers(s);
        ASSERT_LE(depth, 64u);
        for (const PeelOptions& o : {classic(int(depth)), dual(int(depth + 1) / 2)}) {
            if (o.dual && min_t > 0) continue;  // dual applies the threshold to its front layers only
            PeelMethod peel(device(), o);
            const Image img = peel.render(s);
            EXPECT_TRUE(all_finite(img));
            const ImageDiff d = compare_images(img, model, testing::kRelTol, &tol);
            EXPECT_EQ(d.pixels_over, 0u) << peel.name() << " min_t " << min_t << ": " << describe(d);
            // and the model really differs from the reference here.
            EXPECT_GT(compare_images(model, ref, 1e-2).pixels_over, 100u);
        }
    }
}

TEST_F(Peel, EyeInsideSpheresPeelsThemFromTheEyeOneByOne) {
    // Every sphere that contains the eye enters at t0 = 0: a tie broken by sphere index.
    Scene s = small_scene();
    s.camera.position = {0.1, 0.0, 0.2};
    s.spheres.push_back(sphere({0, 0, 0}, 1.5, 0.4, {0.9, 0.9, 0.9}));
    s.spheres.push_back(sphere({0.3, 0.2, 0.1}, 0.8, 1.0, {0.3, 0.6, 0.9}));
    s.spheres.push_back(sphere({0, 0, -2}, 1.8, 0.5, {0.9, 0.5, 0.2}));  // contains the eye too
    s.spheres.push_back(sphere({0, 0, -3}, 0.5, 2.0));
    s.boxes.push_back(Box{{-3, -3, -4.2}, {3, 3, -4}, {0.2, 0.3, 0.1}});
    const Image model = layer_model(s);
    const Image tol = reference_tolerance(s, testing::kRayRelError);
    for (const PeelOptions& o : {classic(8), dual(8), dual(64)}) {
        PeelMethod peel(device(), o);
        const ImageDiff d = compare_images(peel.render(s), model, testing::kRelTol, &tol);
        EXPECT_EQ(d.pixels_over, 0u) << peel.name() << ": " << describe(d);
    }
}

TEST_F(Peel, EmptyScenesAndNewSizes) {
    Scene s = small_scene(40, 30);
    s.boxes.push_back(Box{{-1, -1, -1}, {1, 1, 1}, {0.6, 0.2, 0.1}});
    for (const PeelOptions& o : {classic(8), dual(8)}) {
        PeelMethod peel(device(), o);
        FrameStats stats;
        const ImageDiff empty = compare_with_reference(peel.render(s, &stats), s);  // boxes, no spheres
        EXPECT_EQ(empty.pixels_over, 0u) << peel.name() << ": " << describe(empty);
        EXPECT_EQ(peel.last_frame().passes_drawn, 0);
        Scene t = s;
        t.camera.width = 57;
        t.camera.height = 41;
        t.spheres.push_back(sphere({0.5, 0.5, 1.5}, 0.6, 1.3));
        t.spheres.push_back(sphere({-0.5, 0.2, 2.5}, 0.4, 0.7, {0.2, 0.5, 0.9}));
        const ImageDiff d = compare_with_reference(peel.render(t), t);
        EXPECT_EQ(d.pixels_over, 0u) << peel.name() << ": " << describe(d);
        const ImageDiff again = compare_with_reference(peel.render(s), s);
        EXPECT_EQ(again.pixels_over, 0u) << peel.name() << ": " << describe(again);
    }
}

}  // namespace
}  // namespace brume
