// The preview's heat map of list length (depth complexity) over the view: each pixel whose ray meets
// at least one sphere's clipped interval is tinted by its list length (render/frame/list_heat_map.h),
// from blue (1) through green and yellow to red (the frame's longest list); pixels with no list keep
// the frame. The tint is mixed in linear radiance, divided by the exposure, so after the tone map its
// colours are the ramp's whatever the exposure. Composed on the CPU and presented like the split and
// difference views (app/preview_compare.h): it costs a second pass and two readbacks a frame.
#pragma once

#include "render/image.h"

#include <array>

namespace brume::app {

// How much of the tint a pixel with a list takes.
inline constexpr float kHeatMapOpacity = 0.65f;

// The ramp's sRGB-encoded colour at t in [0, 1] (clamped): blue, cyan, green, yellow, red.
std::array<float, 3> heat_colour(double t);

// `frame` with the heat map of `counts` (the same size) over it; the ramp spans 1 to `longest`.
Image overlay_list_heat_map(const Image& frame, const Image& counts, double longest, double exposure_stops);

}  // namespace brume::app
