// `brume bench scale`: how each exact method's frame time follows the length of the per-pixel lists.
// Random smoke clouds of growing sphere counts (sim/smoke_cloud_scene.h: lists grow as N^1/3, the
// overlap depth stays the same), every exact method, the CPU reference and `sorted` in one run, with
// fragments, mean and longest list and ns per fragment beside each time, and a chart of ms against
// fragments.
#pragma once

#include "app/bench_command.h"

namespace brume::app {

int run_bench_scale(const BenchArgs& args);

}  // namespace brume::app
