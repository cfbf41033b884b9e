// Mouse and keys to the preview's camera and timeline:
//   left drag: orbit   right drag, or shift + left drag: pan   wheel: zoom
//   arrow keys: orbit  + / -: zoom   R: reset to the preset's camera (follow its path again)
//   space: play / pause   , and .: one frame back or forward   Home / End: first / last frame
//   Esc: quit
// Input the UI panel has taken (the mouse over the panel, a text field) is left alone.
#pragma once

#include "app/preview_session.h"
#include "app/preview_window.h"

namespace brume::app {

// Applies `input` (and the keys held now) over `seconds` of wall-clock time. Returns true when the
// view moved (the camera or the frame changed), which the adaptive resolution reads.
bool apply_controls(const WindowInput& input, bool mouse_taken, bool keyboard_taken, double seconds,
                    const PreviewWindow& window, PreviewSession& session);

}  // namespace brume::app
