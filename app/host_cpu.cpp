#include "app/host_cpu.h"

#include "render/simd8.h"
#include "sim/usable_cpus.h"

#include <charconv>
#include <fstream>
#include <sstream>
#include <thread>

namespace brume::app {
namespace {

std::string_view trimmed(std::string_view s) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    while (!s.empty() && blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && blank(s.back())) s.remove_suffix(1);
    return s;
}

int whole_number(std::string_view s) {
    int value = -1;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), value);
    return error == std::errc() && end == s.data() + s.size() && value >= 0 ? value : -1;
}

}  // namespace

CpuInfo parse_cpuinfo(std::string_view text) {
    CpuInfo cpu;
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        const std::string_view line = text.substr(0, eol);
        text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
        if (trimmed(line).empty()) {
            if (!cpu.model_name.empty() || cpu.family >= 0 || cpu.model >= 0) break;  // the first processor's end
            continue;
        }
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos) continue;
        const std::string_view key = trimmed(line.substr(0, colon)), value = trimmed(line.substr(colon + 1));
        if (key == "model name" && cpu.model_name.empty()) cpu.model_name = std::string(value);
        else if (key == "cpu family" && cpu.family < 0) cpu.family = whole_number(value);
        else if (key == "model" && cpu.model < 0) cpu.model = whole_number(value);
    }
    return cpu;
}

std::string describe_cpu(const CpuInfo& cpu, unsigned hardware_threads, bool avx2_fma, bool avx512vl,
                         unsigned usable) {
    std::ostringstream out;
    out << (cpu.model_name.empty() ? "unknown CPU" : cpu.model_name);
    if (cpu.family >= 0 && cpu.model >= 0) out << " (family " << cpu.family << ", model " << cpu.model << ")";
    if (hardware_threads > 0 && usable > 0 && usable < hardware_threads)
        out << ", " << usable << " of " << hardware_threads << " hardware threads usable";
    else if (hardware_threads > 0)
        out << ", " << hardware_threads << (hardware_threads == 1 ? " hardware thread" : " hardware threads");
    out << ", " << (avx2_fma ? "AVX2+FMA" : "no AVX2+FMA") << ", " << (avx512vl ? "AVX-512" : "no AVX-512");
    return out.str();
}

std::string host_cpu_description() {
    std::ifstream file("/proc/cpuinfo");
    std::ostringstream text;
    if (file) text << file.rdbuf();
    return describe_cpu(parse_cpuinfo(text.str()), std::thread::hardware_concurrency(), simd::cpu_has_avx2_fma(),
                        simd::cpu_has_avx512vl(), usable_cpus());
}

}  // namespace brume::app
