// The CPU a benchmark ran on, for its header. Machines of this project's kind differ by up to 5x in
// absolute speed, and not only by hour: on an AMD EPYC (Zen 3) trace took 1.03-1.34x the times another
// machine of the kind had printed while lavapipe took 1.7-5.1x (docs/performance.md, "On an AMD EPYC"). A
// reader comparing two runs has to know whether they came from one machine.
#pragma once

#include <string>
#include <string_view>

namespace brume::app {

// What /proc/cpuinfo says of its first processor; a field it does not give stays empty or -1.
struct CpuInfo {
    std::string model_name;  // "AMD EPYC", "Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz"
    int family = -1;         // "cpu family"
    int model = -1;          // "model"
};

// The first processor's fields of a /proc/cpuinfo text (its lines up to the first blank one).
CpuInfo parse_cpuinfo(std::string_view text);

// One line for a header: "AMD EPYC (family 25, model 1), 2 hardware threads, AVX2+FMA, no AVX-512".
// Where the process may use fewer (`usable`, its affinity mask: taskset, a farm job's CPUs) the
// threads read "2 of 64 hardware threads usable", since every thread count a benchmark prints is the
// usable one. The instruction sets are the ones trace and the sun map pick their code by
// (render/simd8.h).
std::string describe_cpu(const CpuInfo& cpu, unsigned hardware_threads, bool avx2_fma, bool avx512vl,
                         unsigned usable = 0);

// describe_cpu of this machine: /proc/cpuinfo where it can be read ("unknown CPU" where not),
// std::thread's hardware concurrency, the usable CPUs (usable_cpus, sim/usable_cpus.h) and the
// CPU's own answer on its instruction sets.
std::string host_cpu_description();

}  // namespace brume::app
