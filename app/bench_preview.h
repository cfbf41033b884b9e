// `brume bench preview`: the preview's frame, part by part, for every shipped preset. Each preset
// plays in a real window (a scripted `brume preview`: play, wait N frames, quit) at 640x360 with the
// adaptive resolution on, and the figures of the frames after the internal resolution last changed
// are printed side by side: FPS and the wall-clock time of simulate, upload, render, UI and present.
// Beside them, from the same run: the frame path without a window (what `brume play` does: render
// and read back) at the settled and at the full size, the competitor the window's overhead is
// measured against, and the fill ceiling (render/methods/fill_ceiling.h) at the full size. It needs
// a display; without one it says so and exits with status 1.
#pragma once

#include "app/bench_command.h"

namespace brume::app {

int run_bench_preview(const BenchArgs& args);

}  // namespace brume::app
