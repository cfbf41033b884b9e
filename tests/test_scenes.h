// Scene builders the test suites share (a camera looking at the origin from +z, spheres, forces, the
// scenes several methods are checked on), and pieces of the light model written out in double precision,
// independently of the renderers, for the tests that compare against closed forms.
#pragma once

#include "sim/camera_rays.h"
#include "sim/preset.h"
#include "sim/scene.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace brume::testing {

// A w x h view of the origin from (0, 0, 5), integrating everything (min_transmittance 0).
inline Scene small_scene(int w, int h) {
    Scene s;
    s.source = "test";
    s.camera.position = {0.0, 0.0, 5.0};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.width = w;
    s.camera.height = h;
    s.render.min_transmittance = 0.0;
    return s;
}

inline Sphere sphere(glm::dvec3 c, double r, double tau, glm::dvec3 albedo = {0.9, 0.8, 0.7}) {
    Sphere s;
    s.center = c;
    s.radius = r;
    s.extinction = tau;
    s.albedo = albedo;
    return s;
}

// A force of `kind` with every parameter at its default, for presets built in code.
inline ForceDesc force(ForceKind kind) {
    ForceDesc f;
    f.kind = kind;
    return f;
}

// An opaque wall well behind every sphere of the scenes below, so the background is not flat.
inline void add_back_wall(Scene& s) { s.boxes.push_back(Box{{-20, -20, -12}, {20, 20, -10}, {0.3, 0.25, 0.2}}); }

// `count` random spheres (seeded), overlapping freely, in [-2, 2] x [-1, 2] x [-2, 2]: radii 0.1..0.6,
// extinction 0.01..3.2 (log-uniform), random albedo; seen from (0.3, 1.2, 7) down at (0, 0.2, 0).
// `boxes`: a floor under them and a pillar through them.
inline Scene random_scene(int w, int h, int count, unsigned seed, bool boxes) {
    Scene s = small_scene(w, h);
    s.camera.position = {0.3, 1.2, 7.0};
    s.camera.look_at = {0.0, 0.2, 0.0};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < count; ++i)
        s.spheres.push_back(sphere({u(rng) * 4 - 2, u(rng) * 3 - 1, u(rng) * 4 - 2}, 0.1 + 0.5 * u(rng),
                                   std::pow(10.0, u(rng) * 2.5 - 2.0), {u(rng), u(rng), u(rng)}));
    if (boxes) {
        s.boxes.push_back(Box{{-5, -1.5, -5}, {5, -1, 5}, {0.3, 0.3, 0.3}});
        s.boxes.push_back(Box{{-0.5, -1, -0.5}, {0.4, 1.0, 0.6}, {0.8, 0.3, 0.1}});
    }
    return s;
}

// One sphere (radius 1, tau 0.7) at the centre of a 65 x 65 view (odd: the centre pixel's ray goes
// through the sphere centre), a box behind it below and a wall through it at x in [0.3, 0.5] that clips
// its chords: one sphere per pixel, which the methods that composite whole spheres get exactly right.
// `count` random spheres (seeded) under a sun that casts shadows, in [-2, 2] x [0, 2] x [-2, 2] moved by
// `offset`: radii in [r_lo, r_hi), extinction 0.2..3, every `empty_every`-th sphere (when > 0) without
// medium. No camera: for the sun's own structures (render/sun_depth_map.h, render/float_sun_depth.h).
inline Scene random_sun_cloud(int count, unsigned seed, const glm::dvec3& sun_direction, double r_lo = 0.2,
                              double r_hi = 0.8, const glm::dvec3& offset = glm::dvec3(0.0), int empty_every = 0) {
    Scene s;
    s.lighting.shadows = true;
    s.lighting.sun_direction = sun_direction;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-2.0, 2.0), rad(r_lo, r_hi), tau(0.2, 3.0);
    for (int k = 0; k < count; ++k) {
        Sphere sp;
        sp.center = offset + glm::dvec3(pos(rng), pos(rng) * 0.5 + 1.0, pos(rng));
        sp.radius = rad(rng);
        sp.extinction = tau(rng);
        if (empty_every > 0 && k % empty_every == 0) sp.extinction = 0.0;
        s.spheres.push_back(sp);
    }
    return s;
}

inline Scene clipped_sphere_scene() {
    Scene s = small_scene(65, 65);
    s.spheres.push_back(sphere({0, 0, 0}, 1.0, 0.7));
    s.boxes.push_back(Box{{-3, -3, -3}, {3, -0.4, -2}, {0.6, 0.3, 0.1}});
    s.boxes.push_back(Box{{0.3, -2, -2}, {0.5, 2, 2}, {0.1, 0.4, 0.2}});
    return s;
}

// Five spheres whose depth ranges do not overlap, overlapping on screen, listed out of depth order
// (back to front by centre: 0, 3, 2, 4, 1), before the back wall: along every ray their order is their
// centres' order, so back-to-front "over" compositing is exact.
inline Scene stacked_scene(int w = 128, int h = 96) {
    Scene s = small_scene(w, h);
    add_back_wall(s);
    s.spheres.push_back(sphere({0.2, 0.1, -3.2}, 1.2, 0.6, {0.9, 0.3, 0.2}));    // z in [-4.4, -2.0]
    s.spheres.push_back(sphere({-0.3, -0.1, 2.6}, 0.5, 2.5, {0.2, 0.8, 0.3}));   // [2.1, 3.1]
    s.spheres.push_back(sphere({0.0, 0.2, 0.3}, 0.9, 1.0, {0.3, 0.4, 0.95}));    // [-0.6, 1.2]
    s.spheres.push_back(sphere({0.5, -0.3, -1.3}, 0.6, 4.0, {0.95, 0.9, 0.3}));  // [-1.9, -0.7]
    s.spheres.push_back(sphere({-0.4, 0.3, 1.6}, 0.3, 0.8, {0.8, 0.8, 0.8}));    // [1.3, 1.9]
    return s;
}

// A sphere (index 1) circling a static one (index 0) over frames 0..6: in front of it, past it at the
// side, behind it, and back. It overlaps sphere 0 on screen only where their depth ranges are disjoint,
// and the order of the two flips twice. Sphere 2 is a large one behind everything; sphere 3 joins at
// frame 2 and leaves at frame 5. No boxes: each suite adds its own.
inline std::vector<Sphere> circling_spheres(int frame) {
    const glm::dvec3 path[7] = {{0, 0, 2}, {1.5, 0, 1}, {1.5, 0, -1}, {0, 0.05, -2}, {-1.5, 0, -1}, {-1.5, 0, 1}, {0, 0, 2}};
    std::vector<Sphere> spheres = {sphere({0, 0, 0}, 0.5, 2.0, {0.9, 0.2, 0.2}),
                                   sphere(path[frame], 0.4, 3.0, {0.2, 0.9, 0.3}),
                                   sphere({0, 0, -5}, 1.5, 0.7, {0.3, 0.3, 0.9})};
    if (frame >= 2 && frame < 5) spheres.push_back(sphere({0.1, -0.1, 3.0}, 0.2, 5.0, {0.9, 0.9, 0.9}));
    return spheres;
}

// Two dense spheres side by side (centres x = -x_offset at depth z0 and x = +x_offset at z1) that share
// much of their volume: "over" of two separately attenuated spheres is not the integral through the two
// media, and when z0 and z1 are almost equal a tiny step flips their order.
inline Scene intersecting_pair(double x_offset, double tau, double z0, double z1) {
    Scene s = small_scene(128, 96);
    s.spheres.push_back(sphere({-x_offset, 0.0, z0}, 1.0, tau, {0.95, 0.2, 0.1}));
    s.spheres.push_back(sphere({x_offset, 0.0, z1}, 1.0, tau, {0.1, 0.3, 0.95}));
    return s;
}

// Three overlapping spheres of different media before a coloured background: the scene the frame path
// and the method suites render when any non-trivial frame will do.
inline Scene overlapping_scene(int w, int h) {
    Scene s = small_scene(w, h);
    s.spheres.push_back(sphere({-0.3, 0.0, 0.0}, 0.8, 1.5));
    s.spheres.push_back(sphere({0.3, 0.1, 0.2}, 0.7, 2.5, {0.3, 0.6, 0.9}));
    s.spheres.push_back(sphere({0.0, -0.4, -0.5}, 1.0, 0.7));
    s.lighting.background = {0.2, 0.1, 0.05};
    return s;
}

// ---- the light model in double precision (render/reference.h implements the same model) ----

// The media's source radiance along the unit view direction `dir`: ambient plus sun with the Rayleigh
// phase 3/(16 pi) (1 + cos^2 theta) (Barta & Kovács, "Order Independent Transparency with Per-Pixel
// Linked Lists", section 3.5).
inline glm::dvec3 source_radiance(const Scene& s, const glm::dvec3& dir) {
    const double cos_t = glm::dot(glm::normalize(s.lighting.sun_direction), dir);
    return s.lighting.ambient + s.lighting.sun * (3.0 / (16.0 * M_PI)) * (1.0 + cos_t * cos_t);
}

// The part of a ray (eye + t d, d unit) inside a sphere, clipped to [0, t_max]; nothing when empty.
struct Chord {
    double t0, t1;
};
inline std::optional<Chord> chord(const glm::dvec3& eye, const glm::dvec3& d, const Sphere& sp,
                                  double t_max = INFINITY) {
    const glm::dvec3 oc = eye - sp.center;
    const double b = glm::dot(oc, d);
    const double disc = b * b - (glm::dot(oc, oc) - sp.radius * sp.radius);
    if (disc <= 0.0) return std::nullopt;
    const double t0 = std::max(-b - std::sqrt(disc), 0.0), t1 = std::min(-b + std::sqrt(disc), t_max);
    if (t1 <= t0) return std::nullopt;
    return Chord{t0, t1};
}

// The nearest box along the ray (distance 0 when the eye is inside it) and what the ray sees there:
// the box's radiance, or the background at infinity when it meets no box.
struct OpaqueHit {
    double t = INFINITY;
    glm::dvec3 radiance{0.0};
};
inline OpaqueHit opaque_hit(const Scene& s, const glm::dvec3& eye, const glm::dvec3& d) {
    OpaqueHit hit;
    hit.radiance = s.lighting.background;
    for (const Box& b : s.boxes) {
        double tn = -INFINITY, tf = INFINITY;
        for (int a = 0; a < 3; ++a) {
            const double t1 = (b.min[a] - eye[a]) / d[a], t2 = (b.max[a] - eye[a]) / d[a];
            tn = std::max(tn, std::min(t1, t2));
            tf = std::min(tf, std::max(t1, t2));
        }
        if (tf >= std::max(tn, 0.0) && std::max(tn, 0.0) < hit.t) {
            hit.t = std::max(tn, 0.0);
            hit.radiance = b.radiance;
        }
    }
    return hit;
}

// Pixel (i, j) of a scene whose only sphere is spheres[0]: albedo L_s (1 - T) + T L_behind with
// T = exp(-tau l), l the chord clipped by the eye and the nearest box.
inline glm::dvec3 single_sphere_radiance(const Scene& s, int i, int j) {
    const CameraRays rays = make_camera_rays(s.camera);
    const glm::dvec3 d = rays.pixel_direction(i, j);
    const OpaqueHit behind = opaque_hit(s, rays.eye, d);
    const std::optional<Chord> c = chord(rays.eye, d, s.spheres.at(0), behind.t);
    const double t = c ? std::exp(-s.spheres[0].extinction * (c->t1 - c->t0)) : 1.0;
    return s.spheres[0].albedo * source_radiance(s, d) * (1.0 - t) + t * behind.radiance;
}

// 100 nearly coincident unit spheres at the origin (jitter 0.01): every medium is open at once, more
// than any register window of the exact resolves holds, so their general paths must take over.
inline Scene nearly_coincident_scene(int w, int h) {
    Scene s = small_scene(w, h);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    for (int i = 0; i < 100; ++i)
        s.spheres.push_back(sphere({jitter(rng), jitter(rng), jitter(rng)}, 1.0, 0.02, {0.9, 0.6 + 0.003 * i, 0.5}));
    return s;
}

// One pixel's list of `nodes` spheres at 15 x 15 (the centre pixel's ray is the view axis): a chain of
// disjoint spheres along the axis (nearly sorted), or coincident spheres (every medium open at once).
// Thin: optical depth 1 through the centre and no early stop; thick: 40 (coincident) or 100 (chain),
// stopping at transmittance 1e-4.
struct LongList {
    int nodes;
    bool coincident;
    bool thick;
};

inline Scene long_list_scene(const LongList& p) {
    Scene s = small_scene(15, 15);
    s.render.min_transmittance = p.thick ? 1e-4 : 0.0;
    for (int i = 0; i < p.nodes; ++i) {
        if (p.coincident) {
            s.spheres.push_back(sphere({0, 0, 0}, 0.5, (p.thick ? 40.0 : 1.0) / p.nodes, {0.9, 0.7, 0.5}));
        } else {
            const double spacing = 2.0 / p.nodes;  // centres from z = 1 down to z = -1, radius 0.4 spacing
            s.spheres.push_back(sphere({0, 0, 1.0 - spacing * i}, 0.4 * spacing, (p.thick ? 100.0 : 1.0) / 0.8,
                                       {0.9, 0.7, 0.5}));
        }
    }
    return s;
}

// The long lists: 800, 3,000 and 20,000 nodes, chains and coincident stacks, thin and thick;
// with_400 adds the coincident 400, the longest the general path resolves on lavapipe.
inline std::vector<LongList> long_lists(bool with_400 = false) {
    std::vector<LongList> out;
    for (const bool coincident : {false, true}) {
        if (coincident && with_400) {
            out.push_back({400, true, false});
            out.push_back({400, true, true});
        }
        for (const int nodes : {800, 3000, 20000}) {
            out.push_back({nodes, coincident, false});
            out.push_back({nodes, coincident, true});
        }
    }
    return out;
}

inline std::string long_list_name(const LongList& p) {
    return std::to_string(p.nodes) + (p.coincident ? "_coincident" : "_chain") + (p.thick ? "_thick" : "_thin");
}

// A sparse cloud of `count` dense puffs (seeded): radii 0.1-0.4, extinction 1-30 per unit (log-uniform),
// in a cluster about 3 units across over a diffuse ground, under a sun from the side and little ambient
// light, seen from 5.6 units through 30 degrees. The scenes where a lattice blurs each puff's shadow edge, which its
// neighbours do not average away, past the accurate technique's target (docs/accuracy.md, "Sparse
// clouds"); the map takes up to SunDepthMap::kMaxColumnSpheres of them through its columns.
inline Scene sparse_puff_cloud(int count, unsigned seed, int w = 64, int h = 48) {
    Scene s = small_scene(w, h);
    s.camera.position = {4.4, 1.7, 3.1};
    s.camera.look_at = {0.0, 0.3, 0.0};
    s.camera.fov_y_deg = 30.0;
    s.lighting.ambient = {0.05, 0.05, 0.06};
    s.lighting.sun = {1.5, 1.4, 1.2};
    s.lighting.sun_direction = {-0.55, -0.7, 0.45};
    s.lighting.background = {0.1, 0.12, 0.16};
    s.lighting.shadows = true;
    s.render.shadow_technique = ShadowTechnique::Accurate;
    Box ground{{-20.0, -2.0, -20.0}, {20.0, -1.0, 20.0}, {0.0, 0.0, 0.0}};
    ground.diffuse = {0.5, 0.5, 0.5};
    s.boxes = {ground};
    std::mt19937 rng(seed);
    std::normal_distribution<double> across(0.0, 0.75), up(0.3, 0.5);
    std::uniform_real_distribution<double> radius(0.1, 0.4), log_extinction(0.0, std::log(30.0));
    for (int k = 0; k < count; ++k) {
        const glm::dvec3 c{across(rng), up(rng), across(rng)};
        const double r = radius(rng);
        s.spheres.push_back(sphere(c, r, std::exp(log_extinction(rng)), {0.9, 0.9, 0.9}));
    }
    return s;
}

// A smoke cloud over a lit ground under a low sun, a box among the spheres casting its own shadow, seen
// from outside and from inside the smoke. Of 24 spheres, which the accurate technique's map takes
// whole (render/sun_depth_map.h kMaxWholeSpheres), of kColumnCloudSpheres, which it takes through its
// columns (at most kMaxColumnSpheres of smoke this dense), or of kLatticeCloudSpheres, more than that:
// its lattice holds them.
inline constexpr int kColumnCloudSpheres = 100;
inline constexpr int kLatticeCloudSpheres = 280;
inline Scene shadowed_cloud(bool eye_inside, int spheres = 24) {
    Scene s = random_scene(64, 48, spheres, 11, false);
    s.lighting.shadows = true;
    s.lighting.sun_direction = {-0.7, -0.6, -0.3};
    Box ground{{-8, -1.5, -8}, {8, -1, 8}, {0.0, 0.0, 0.0}};
    ground.diffuse = {0.6, 0.6, 0.6};
    Box pillar{{-0.3, -1, -0.3}, {0.3, 0.8, 0.3}, {0.0, 0.0, 0.0}};
    pillar.diffuse = {0.4, 0.4, 0.4};
    s.boxes = {ground, pillar};
    if (eye_inside) {
        s.camera.position = s.spheres[0].center + glm::dvec3(0.0, 0.0, 0.05);
        s.camera.look_at = {0.0, 0.0, 0.0};
    }
    return s;
}

}  // namespace brume::testing
