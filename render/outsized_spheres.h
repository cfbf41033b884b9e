// Spheres far larger than the rest of the scene: an atmosphere around it, a fog bank around a few puffs.
// Every light-space structure (SunDepthMap's lattice, SunLight's and FloatSunDepth's grids, the GPU's
// copies) leaves them out and adds their chords toward the sun in closed form, a square root each.
// In a grid or lattice sized from the spheres' mean radius and spanning their discs, one such sphere set
// the spacing and the extent: the map's spacing grew to about 225 units around three puffs of radius 1
// (their shadows blurred away), and the light grids' cells listed every puff in every cell (the
// reference took 3.1 s a frame against 1.5 s). One rule for all of them, so that they agree on which
// spheres are taken so. The depth map alone also takes every sphere of a scene of at most 48
// whole (render/sun_depth_map.h kMaxWholeSpheres); the device's build of the map then has nothing to splat
// (render/frame/frame_resources.cpp).
#pragma once

#include "sim/scene.h"

#include <cstddef>
#include <vector>

namespace brume {

// A sphere is outsized over this many times the median radius, and at most this many are taken so.
constexpr double kOutsizedRadii = 16.0;
constexpr int kMaxOutsized = 8;

// Among the scene's spheres with a medium (extinction > 0 and radius > 0: the others add no optical
// depth, and no light-space structure holds them), the outsized ones, as ascending indices into
// scene.spheres: each over kOutsizedRadii times the median radius of those spheres, the largest
// kMaxOutsized of them (ties in scene order), and none unless a sphere is left for the grid. No shipped
// preset has one (its largest radius is at most 2.1 times its median), so their grids and maps are as
// they were without the rule.
std::vector<std::size_t> outsized_spheres(const Scene& scene);

// How many of those spheres are over kOutsizedRadii times the median radius, before the rule keeps the
// largest kMaxOutsized (0 where none would be left for the grid): past kMaxOutsized the rest stay in
// the map's lattice and set its spacing (in a scene of more than SunDepthMap::kMaxWholeSpheres spheres;
// a smaller one has every sphere whole), and the accurate technique misses its error target
// (docs/accuracy.md, "Scenes the map's spacing does not fit"). The commands say so.
std::size_t outsized_sphere_count(const Scene& scene);

}  // namespace brume
