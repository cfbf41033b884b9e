// `brume bench [methods] -o DIR`: every method on every scene, charted (README.md, "Methods
// compared"): median GPU ms, memory, error against the CPU reference, the temporal popping error
// (temporal_error, render/image_compare.h), and the error by depth complexity; results.csv,
// results.json and gnuplot charts in DIR.
#pragma once

#include "app/bench_command.h"

#include <CLI/CLI.hpp>

namespace brume::app {

void add_bench_methods_options(CLI::App& bench, BenchArgs& args);
int run_bench_methods(const BenchArgs& args);

}  // namespace brume::app
