// The CPU line of the benchmarks' headers (app/host_cpu.h): what /proc/cpuinfo says, read right.
#include "app/host_cpu.h"
#include "sim/parallel_for.h"
#include "sim/usable_cpus.h"

#include <gtest/gtest.h>

#include <sched.h>
#include <unistd.h>

#include <string>
#include <thread>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

using brume::app::CpuInfo;
using brume::app::describe_cpu;
using brume::app::parse_cpuinfo;

namespace {

// The start of /proc/cpuinfo on this project's machines (two processors; the second one's fields differ
// here so that a parser reading past the first would be caught).
constexpr const char* kAmd =
    "processor\t: 0\n"
    "vendor_id\t: AuthenticAMD\n"
    "cpu family\t: 25\n"
    "model\t\t: 1\n"
    "model name\t: AMD EPYC\n"
    "stepping\t: 1\n"
    "flags\t\t: fpu vme de pse tsc msr avx2 fma\n"
    "\n"
    "processor\t: 1\n"
    "vendor_id\t: AuthenticAMD\n"
    "cpu family\t: 26\n"
    "model\t\t: 2\n"
    "model name\t: Another CPU\n"
    "\n";

constexpr const char* kIntel =
    "processor\t: 0\n"
    "vendor_id\t: GenuineIntel\n"
    "cpu family\t: 6\n"
    "model\t\t: 106\n"
    "model name\t: Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz\n"
    "stepping\t: 6\n";

}  // namespace

TEST(HostCpu, ReadsTheFirstProcessorsModelFamilyAndModel) {
    const CpuInfo amd = parse_cpuinfo(kAmd);
    EXPECT_EQ(amd.model_name, "AMD EPYC");
    EXPECT_EQ(amd.family, 25);
    EXPECT_EQ(amd.model, 1);
    const CpuInfo intel = parse_cpuinfo(kIntel);  // no blank line at its end
    EXPECT_EQ(intel.model_name, "Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz");
    EXPECT_EQ(intel.family, 6);
    EXPECT_EQ(intel.model, 106);
}

TEST(HostCpu, ATextWithoutTheFieldsLeavesThemUnknown) {
    for (const char* text : {"", "\n\n", "no colon here\n", "cpu family\t: twenty\nmodel\t: -3\n"}) {
        const CpuInfo cpu = parse_cpuinfo(text);
        EXPECT_TRUE(cpu.model_name.empty()) << text;
        EXPECT_EQ(cpu.family, -1) << text;
        EXPECT_EQ(cpu.model, -1) << text;
    }
    // Leading blank lines are no processor's end.
    EXPECT_EQ(parse_cpuinfo("\n\nmodel name : X\n").model_name, "X");
}

TEST(HostCpu, DescribesTheCpuInOneLine) {
    EXPECT_EQ(describe_cpu(parse_cpuinfo(kAmd), 2, true, false),
              "AMD EPYC (family 25, model 1), 2 hardware threads, AVX2+FMA, no AVX-512");
    EXPECT_EQ(describe_cpu(parse_cpuinfo(kIntel), 1, true, true),
              "Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz (family 6, model 106), 1 hardware thread, AVX2+FMA, "
              "AVX-512");
    EXPECT_EQ(describe_cpu(CpuInfo{}, 0, false, false), "unknown CPU, no AVX2+FMA, no AVX-512");
    // A process held to fewer CPUs than the machine has (taskset, a farm job) says so.
    EXPECT_EQ(describe_cpu(parse_cpuinfo(kAmd), 64, true, false, 2),
              "AMD EPYC (family 25, model 1), 2 of 64 hardware threads usable, AVX2+FMA, no AVX-512");
    EXPECT_EQ(describe_cpu(parse_cpuinfo(kAmd), 2, true, false, 2),
              "AMD EPYC (family 25, model 1), 2 hardware threads, AVX2+FMA, no AVX-512");
}

// The CPUs a process may use are its affinity mask's (taskset, a Slurm job's --cpus-per-task), not the
// machine's: held to one CPU, the tracers run one worker, and describe_cpu says so.
TEST(HostCpu, UsableCpusFollowTheAffinityMask) {
    cpu_set_t saved;
    ASSERT_EQ(::sched_getaffinity(0, sizeof saved, &saved), 0);
    // The mask's CPUs, or fewer where this machine's control group sets a CPU quota.
    std::ifstream self("/proc/self/cgroup");
    std::stringstream self_text;
    self_text << self.rdbuf();
    const unsigned quota = brume::cgroup_cpu_limit("/sys/fs/cgroup", self_text.str());
    const unsigned all = unsigned(CPU_COUNT(&saved)), expected = quota > 0 ? std::min(all, quota) : all;
    EXPECT_EQ(brume::usable_cpus(), expected);
    int first = 0;
    while (!CPU_ISSET(first, &saved)) ++first;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    ASSERT_EQ(::sched_setaffinity(0, sizeof one, &one), 0);
    EXPECT_EQ(brume::usable_cpus(), 1u);
    EXPECT_EQ(brume::worker_count(0, 1000), 1);
    EXPECT_EQ(brume::worker_count(3, 1000), 3);  // a count asked for is kept
    const std::string line = brume::app::host_cpu_description();
    ASSERT_EQ(::sched_setaffinity(0, sizeof saved, &saved), 0);
    if (std::thread::hardware_concurrency() > 1) {
        EXPECT_NE(line.find("1 of " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads usable"),
                  std::string::npos)
            << line;
    }
    EXPECT_EQ(brume::usable_cpus(), expected);
}

// A command's --threads caps usable_cpus for the whole run (cap_usable_cpus), so that the loops that
// ask for every CPU (a GPU method's depth map and binning, a volume's import) stay within it; 0 lifts
// the cap.
TEST(HostCpu, ACapHoldsEveryLoopThatAsksForAllCpus) {
    const unsigned all = brume::usable_cpus();
    brume::cap_usable_cpus(1);
    EXPECT_EQ(brume::usable_cpus(), 1u);
    EXPECT_EQ(brume::worker_count(0, 1000), 1);
    EXPECT_EQ(brume::worker_count(3, 1000), 3);  // a count asked for is kept
    brume::cap_usable_cpus(all + 5);             // a cap above the CPUs changes nothing
    EXPECT_EQ(brume::usable_cpus(), all);
    brume::cap_usable_cpus(0);
    EXPECT_EQ(brume::usable_cpus(), all);
}

// A CPU quota (docker --cpus, a Kubernetes CPU limit) is read from the control group's files, v2 and
// v1, the tightest of the group and those above it, rounded up; none, "max" or -1 is no limit.
TEST(HostCpu, ACgroupCpuQuotaLimitsTheUsableCpus) {
    namespace fs = std::filesystem;
    const fs::path root = fs::temp_directory_path() / ("brume_cgroup_" + std::to_string(::getpid()));
    fs::remove_all(root);
    const auto put = [](const fs::path& file, const std::string& text) {
        fs::create_directories(file.parent_path());
        std::ofstream(file) << text;
    };
    // cgroup v2
    put(root / "v2" / "cpu.max", "max 100000\n");
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v2", "0::/\n"), 0u);
    put(root / "v2" / "kubepods" / "pod" / "cpu.max", "150000 100000\n");
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v2", "0::/kubepods/pod\n"), 2u);  // 1.5 CPUs: 2 threads
    put(root / "v2" / "kubepods" / "cpu.max", "100000 100000\n");
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v2", "0::/kubepods/pod\n"), 1u);  // the parent's is tighter
    put(root / "v2" / "small" / "cpu.max", "20000 100000\n");
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v2", "0::/small"), 1u);  // a fifth of a CPU still runs one
    // cgroup v1, the cpu controller mounted with cpuacct, beside the unified hierarchy's line
    put(root / "v1" / "cpu,cpuacct" / "job" / "cpu.cfs_quota_us", "400000\n");
    put(root / "v1" / "cpu,cpuacct" / "job" / "cpu.cfs_period_us", "100000\n");
    put(root / "v1" / "cpu,cpuacct" / "cpu.cfs_quota_us", "-1\n");
    put(root / "v1" / "cpu,cpuacct" / "cpu.cfs_period_us", "100000\n");
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v1", "5:memory:/job\n4:cpu,cpuacct:/job\n0::/job\n"), 4u);
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v1", "4:cpu,cpuacct:/\n0::/\n"), 0u);
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v1", "4:cpuacct,cpu:/job\n"), 0u);  // no such mount: no limit read
    // Text that is not a cgroup listing, and groups without the files, set no limit.
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "v2", "garbage"), 0u);
    EXPECT_EQ(brume::cgroup_cpu_limit(root / "nowhere", "0::/a/b\n"), 0u);
    fs::remove_all(root);
    // Whatever this machine's groups say, the process keeps at least one CPU and no more than its mask.
    cpu_set_t mask;
    ASSERT_EQ(::sched_getaffinity(0, sizeof mask, &mask), 0);
    EXPECT_GE(brume::usable_cpus(), 1u);
    EXPECT_LE(brume::usable_cpus(), unsigned(CPU_COUNT(&mask)));
}

TEST(HostCpu, ThisMachinesLineNamesItsOwnCpu) {
    std::ifstream file("/proc/cpuinfo");
    if (!file) GTEST_SKIP() << "no /proc/cpuinfo here";
    std::ostringstream text;
    text << file.rdbuf();
    const CpuInfo cpu = parse_cpuinfo(text.str());
    const std::string line = brume::app::host_cpu_description();
    EXPECT_EQ(line.rfind(cpu.model_name.empty() ? "unknown CPU" : cpu.model_name, 0), 0u) << line;
    EXPECT_NE(line.find("hardware thread"), std::string::npos) << line;
}
