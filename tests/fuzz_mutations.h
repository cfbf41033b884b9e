// The seeded mutations both fuzz runs apply to the shipped presets and test scenes: byte flips,
// truncation, deep nesting, huge numbers, wrong types, long strings and keys, duplicated lines and moved
// chunks. tests/test_fuzz_inputs.cpp feeds thousands of them to the readers; tests/test_fuzz_cli.cpp
// feeds a sample to the brume binary itself.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <filesystem>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace brume::fuzz {

// One file the fuzz runs mutate; `preset`: presets/*.toml but default.toml (the built-in scene) are
// preset files, the others (tests/data, examples) scene files.
struct Input {
    std::filesystem::path path;
    bool preset;
};

// Every shipped preset, test scene and example under the source tree `root`, in path order, so that a
// seeded run mutates the same files in the same order on every machine.
inline std::vector<Input> inputs(const std::filesystem::path& root) {
    std::vector<Input> out;
    for (const char* dir : {"presets", "tests/data", "examples"})
        for (const auto& e : std::filesystem::directory_iterator(root / dir))
            if (e.path().extension() == ".toml")
                out.push_back({e.path(), std::string(dir) == "presets" && e.path().filename() != "default.toml"});
    std::sort(out.begin(), out.end(), [](const Input& a, const Input& b) { return a.path < b.path; });
    return out;
}

// Positions of number tokens (a digit not inside a word) in the text.
inline std::vector<std::size_t> numbers(const std::string& t) {
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < t.size(); ++i)
        if (std::isdigit(static_cast<unsigned char>(t[i])) && (i == 0 || !std::isalnum(static_cast<unsigned char>(t[i - 1])) ) &&
            (i == 0 || t[i - 1] != '_'))
            at.push_back(i);
    return at;
}

inline std::string replace_number(const std::string& t, std::mt19937_64& rng, const std::string& with) {
    const std::vector<std::size_t> at = numbers(t);
    if (at.empty()) return t + "\nx = " + with + "\n";
    const std::size_t i = at[rng() % at.size()];
    std::size_t j = i;
    while (j < t.size() && (std::isalnum(static_cast<unsigned char>(t[j])) || t[j] == '.' || t[j] == '+' || t[j] == '-')) ++j;
    return t.substr(0, i) + with + t.substr(j);
}

inline std::string mutate(const std::string& t, std::mt19937_64& rng) {
    static const char* huge[] = {"1e308", "-1e308", "9223372036854775807", "-9223372036854775808", "99999999999999999999",
                                 "nan", "inf", "-inf", "1e-320", "4294967296", "0"};
    static const char* wrong[] = {"\"text\"", "true", "[1, 2]", "{ a = 1 }", "[]", "1979-05-27", "[[1], [2]]", "\"\""};
    const std::size_t at = t.empty() ? 0 : rng() % t.size();
    switch (rng() % 8) {
        case 0: {  // byte flips
            std::string m = t;
            for (int k = 0, n = 1 + int(rng() % 4); k < n && !m.empty(); ++k) m[rng() % m.size()] = char(rng() % 256);
            return m;
        }
        case 1: return t.substr(0, at);  // truncation
        case 2: {  // deep nesting, on both sides of the bound
            const int depth = 32 + int(rng() % 200);
            std::string line;
            switch (rng() % 3) {
                case 0:
                    line = "a";
                    for (int k = 0; k < depth; ++k) line += ".a";
                    line += " = 1";
                    break;
                case 1: line = "x = " + std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']'); break;
                default:
                    line = "y = ";
                    for (int k = 0; k < depth; ++k) line += "{ a = ";
                    line += "1" + std::string(std::size_t(depth), '}');
            }
            const std::size_t nl = t.find('\n', at);
            return nl == std::string::npos ? t + "\n" + line + "\n" : t.substr(0, nl + 1) + line + "\n" + t.substr(nl + 1);
        }
        case 3: return replace_number(t, rng, huge[rng() % std::size(huge)]);  // huge numbers
        case 4: return replace_number(t, rng, wrong[rng() % std::size(wrong)]);  // wrong types
        case 5: {  // a long string value, or a long key
            const std::string big(std::size_t(1000 + rng() % 100000), char('a' + rng() % 26));
            if (rng() % 2) return replace_number(t, rng, "\"" + big + "\"");
            const std::size_t nl = t.find('\n', at);
            const std::string line = big + " = 1";
            return nl == std::string::npos ? t + "\n" + line : t.substr(0, nl + 1) + line + "\n" + t.substr(nl + 1);
        }
        case 6: {  // a line duplicated (duplicate keys, repeated tables)
            const std::size_t a = t.rfind('\n', at), b = t.find('\n', at);
            const std::size_t s = a == std::string::npos ? 0 : a + 1;
            const std::string line = t.substr(s, b == std::string::npos ? std::string::npos : b - s);
            return t.substr(0, s) + line + "\n" + t.substr(s);
        }
        default: {  // a chunk moved elsewhere
            const std::size_t len = std::min<std::size_t>(t.size() - at, 1 + rng() % 64);
            std::string chunk = t.substr(at, len), rest = t.substr(0, at) + t.substr(at + len);
            const std::size_t to = rest.empty() ? 0 : rng() % rest.size();
            return rest.substr(0, to) + chunk + rest.substr(to);
        }
    }
}

}  // namespace brume::fuzz
