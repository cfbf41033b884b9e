// Two methods side by side: the left half of the view shows the method, the right half another one
// (ppll beside sorted, to watch popping), split by a one-pixel white line; or the difference view,
// |method - other| per channel times 8 (3 stops), which shows where and how much they disagree.
// Both frames are read back through the frame path and composed on the CPU, on the preview's render
// thread (app/preview_renderer.h); the composite is presented as every frame of the view is
// (app/preview_image_presenter.h). It costs two frames and a readback each.
#pragma once

#include "render/image.h"

namespace brume::app {

enum class CompareMode { Off, Split, Difference };

inline constexpr float kDifferenceGain = 8.0f;

// The composite of `method` (left, or the minuend) and `other` (same size). Split: columns left of
// width / 2 are `method`'s, the column at width / 2 is white (radiance 1), the rest `other`'s.
Image compose_comparison(const Image& method, const Image& other, CompareMode mode);

}  // namespace brume::app
