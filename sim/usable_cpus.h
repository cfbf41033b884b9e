// How many CPUs this process may keep busy: what `threads = 0` means for every parallel loop
// (sim/parallel_for.h), and what the benchmarks' host line reports.
#pragma once

#include <filesystem>
#include <string_view>

namespace brume {

// The CPUs of the process's affinity mask (taskset, a Slurm job's --cpus-per-task, docker
// --cpuset-cpus), not std::thread::hardware_concurrency(), which counts every CPU of the machine (a
// two-CPU farm job on a 64-core node took 64 threads, 32 to a CPU); and fewer where the process's
// control group has a CPU quota (docker --cpus, a Kubernetes pod's CPU limit): the quota over its
// period, rounded up. The quota is read once a process; the mask at every call.
unsigned usable_cpus();

// Holds usable_cpus() to at most `n` for the rest of the process (0: no cap): a command's --threads,
// so that every parallel loop of a run (the CPU tracers, and for a GPU method the host's share of
// the frame: the accurate shadows' depth map, tiles' binning; a volume's import) stays within what
// a job on a shared machine was given.
void cap_usable_cpus(unsigned n);

// The CPUs that the quota of the control group a process is in allows, and of every group above it,
// the tightest rounded up; 0 where none sets one. `root` is where the cgroup filesystems are mounted
// (/sys/fs/cgroup), `self_cgroup` the text of /proc/self/cgroup: cgroup v2 (cpu.max, "max 100000"
// or "QUOTA PERIOD") and v1 (cpu.cfs_quota_us, -1 for none, over cpu.cfs_period_us, under the cpu
// controller's mount). Apart from usable_cpus for its tests, which build the files in a folder.
unsigned cgroup_cpu_limit(const std::filesystem::path& root, std::string_view self_cgroup);

}  // namespace brume
