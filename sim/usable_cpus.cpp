#include "sim/usable_cpus.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace brume {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    if (in) text << in.rdbuf();
    return text.str();
}

// The first whitespace-separated words of `text` as numbers: false where one is missing or not a
// whole number ("max" is not).
bool read_numbers(std::string_view text, long long* values, int count) {
    std::size_t at = 0;
    for (int k = 0; k < count; ++k) {
        while (at < text.size() && (text[at] == ' ' || text[at] == '\n' || text[at] == '\t')) ++at;
        const char* first = text.data() + at;
        const auto [end, error] = std::from_chars(first, text.data() + text.size(), values[k]);
        if (error != std::errc() || end == first) return false;
        at = std::size_t(end - text.data());
    }
    return true;
}

// CPUs allowed by a quota of `quota` microseconds each `period`, rounded up; 0 for none.
unsigned cpus_of_quota(long long quota, long long period) {
    if (quota <= 0 || period <= 0) return 0;
    return unsigned(std::max(1.0, std::ceil(double(quota) / double(period))));
}

// The tightest limit of `dir` and the folders above it up to `root` (a limit set on a parent holds
// for its children too), by `limit_in`; 0 where none sets one.
template <class LimitIn>
unsigned tightest_up_to(const fs::path& root, const fs::path& dir, const LimitIn& limit_in) {
    unsigned tightest = 0;
    for (fs::path at = dir;; at = at.parent_path()) {
        if (const unsigned limit = limit_in(at); limit > 0) tightest = tightest == 0 ? limit : std::min(tightest, limit);
        if (at == root || at.parent_path() == at || at.string().size() <= root.string().size()) break;
    }
    return tightest;
}

}  // namespace

unsigned cgroup_cpu_limit(const fs::path& root, std::string_view self_cgroup) {
    unsigned tightest = 0;
    const auto keep = [&tightest](unsigned limit) {
        if (limit > 0) tightest = tightest == 0 ? limit : std::min(tightest, limit);
    };
    std::size_t start = 0;
    while (start < self_cgroup.size()) {
        std::size_t end = self_cgroup.find('\n', start);
        if (end == std::string_view::npos) end = self_cgroup.size();
        const std::string_view line = self_cgroup.substr(start, end - start);
        start = end + 1;
        // "ID:CONTROLLERS:PATH"; the path is relative to each hierarchy's mount.
        const std::size_t first = line.find(':'), second = line.find(':', first + 1);
        if (first == std::string_view::npos || second == std::string_view::npos) continue;
        const std::string controllers(line.substr(first + 1, second - first - 1));
        const std::string path(line.substr(second + 1));
        const fs::path relative = fs::path(path).relative_path();
        if (controllers.empty()) {  // cgroup v2: cpu.max
            keep(tightest_up_to(root, root / relative, [](const fs::path& dir) {
                long long v[2];
                const std::string text = read_text(dir / "cpu.max");
                return read_numbers(text, v, 2) ? cpus_of_quota(v[0], v[1]) : 0u;
            }));
            continue;
        }
        // cgroup v1: the cpu controller, mounted as "cpu", "cpu,cpuacct" or the like.
        bool has_cpu = false;
        for (std::size_t a = 0; a <= controllers.size();) {
            const std::size_t b = std::min(controllers.find(',', a), controllers.size());
            has_cpu = has_cpu || controllers.compare(a, b - a, "cpu") == 0;
            a = b + 1;
        }
        if (!has_cpu) continue;
        for (const fs::path& mount : {root / controllers, root / "cpu"}) {
            std::error_code ec;
            if (!fs::is_directory(mount, ec)) continue;
            keep(tightest_up_to(mount, mount / relative, [](const fs::path& dir) {
                long long quota = 0, period = 0;
                return read_numbers(read_text(dir / "cpu.cfs_quota_us"), &quota, 1) &&
                               read_numbers(read_text(dir / "cpu.cfs_period_us"), &period, 1)
                           ? cpus_of_quota(quota, period)
                           : 0u;
            }));
            break;
        }
    }
    return tightest;
}

namespace {
std::atomic<unsigned> usable_cap{0};  // cap_usable_cpus
}  // namespace

void cap_usable_cpus(unsigned n) { usable_cap.store(n); }

unsigned usable_cpus() {
    static const unsigned quota_limit = cgroup_cpu_limit("/sys/fs/cgroup", read_text("/proc/self/cgroup"));
    unsigned cpus = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) == 0) cpus = unsigned(CPU_COUNT(&set));
    if (cpus == 0) cpus = std::max(1u, std::thread::hardware_concurrency());  // more CPUs than a cpu_set_t holds
    if (quota_limit > 0) cpus = std::min(cpus, quota_limit);
    const unsigned cap = usable_cap.load();
    return cap > 0 ? std::min(cpus, cap) : cpus;
}

}  // namespace brume
