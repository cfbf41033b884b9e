// `brume bench vdb`: OpenVDB import at several tolerances on built-in sample clouds of several sizes:
// read time, conversion time, sphere count and the optical-depth error measured over the axis views,
// side by side, with a sphere-count-against-error chart when -o names a directory.
#pragma once

#include "app/bench_command.h"

namespace brume::app {

int run_bench_vdb(const BenchArgs& args);

}  // namespace brume::app
