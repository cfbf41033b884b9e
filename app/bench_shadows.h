// `brume bench shadows`: the shadow techniques (none, per-sphere, accurate; docs/accuracy.md) on shadowed
// scenes and animations, speed against accuracy. Each technique's error against the exact CPU reference
// (mean and p99.9 over the peak, and the temporal error across an animation's frames) beside its frame
// time by ppll, tiles and trace; the frame without shadows is the ceiling each technique's cost is a
// multiple of (the techniques timed in turn, round after round, each round's ratio its own), the exact
// reference the competitor, both timed in the same run (--no-reference: the ratios alone). A chart of
// ms against mean error with -o.
#pragma once

#include "app/bench_command.h"

namespace brume::app {

int run_bench_shadows(const BenchArgs& args);

}  // namespace brume::app
