// A bounded, seeded fuzz run of the scene and preset readers (issue 14, "Tests"): mutations of every
// shipped preset and test scene (byte flips, truncation, deep nesting, huge numbers, long strings,
// wrong types). Every mutation must parse or fail with one std::exception whose message is a
// single line of bounded length; a crash, a hang (ctest's timeout) or anything else fails the test.
// tests/cli_errors.sh runs a sample of such files through the brume binary, where a failed run must
// also leave an existing output byte-identical.
#include "sim/preset_file.h"
#include "sim/scene_file.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace brume {
namespace {

namespace fs = std::filesystem;

// The longest message any rejected mutation may produce: the list of allowed keys fits, an echoed
// 100,000-byte value does not.
constexpr std::size_t kMaxMessage = 1000;

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

struct Input {
    fs::path path;
    std::string text;
    bool preset;  // presets/*.toml but default.toml (the built-in scene) are preset files
};

std::vector<Input> inputs() {
    std::vector<Input> out;
    const fs::path root = BRUME_SOURCE_DIR;
    for (const char* dir : {"presets", "tests/data", "examples"})
        for (const auto& e : fs::directory_iterator(root / dir))
            if (e.path().extension() == ".toml")
                out.push_back({e.path(), read(e.path()),
                               std::string(dir) == "presets" && e.path().filename() != "default.toml"});
    return out;
}

// Positions of number tokens (a digit not inside a word) in the text.
std::vector<std::size_t> numbers(const std::string& t) {
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < t.size(); ++i)
        if (std::isdigit(static_cast<unsigned char>(t[i])) && (i == 0 || !std::isalnum(static_cast<unsigned char>(t[i - 1])) ) &&
            (i == 0 || t[i - 1] != '_'))
            at.push_back(i);
    return at;
}

std::string replace_number(const std::string& t, std::mt19937_64& rng, const std::string& with) {
    const std::vector<std::size_t> at = numbers(t);
    if (at.empty()) return t + "\nx = " + with + "\n";
    const std::size_t i = at[rng() % at.size()];
    std::size_t j = i;
    while (j < t.size() && (std::isalnum(static_cast<unsigned char>(t[j])) || t[j] == '.' || t[j] == '+' || t[j] == '-')) ++j;
    return t.substr(0, i) + with + t.substr(j);
}

std::string mutate(const std::string& t, std::mt19937_64& rng) {
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

TEST(FuzzInputs, EveryMutationParsesOrFailsWithOneBoundedLine) {
    const std::vector<Input> files = inputs();
    ASSERT_GE(files.size(), 10u) << "the shipped presets and test scenes were not found under " << BRUME_SOURCE_DIR;
    std::mt19937_64 rng(20261202);  // seeded: a failure reproduces
    const auto start = std::chrono::steady_clock::now();
    int cases = 0, rejected = 0;
    for (const Input& f : files) {
        for (int k = 0; k < 300; ++k) {
            const std::string text = mutate(f.text, rng);
            ++cases;
            try {
                if (f.preset)
                    (void)parse_preset_toml(text, f.path.filename().string());
                else
                    (void)parse_scene_toml(text, f.path.filename().string());
            } catch (const std::exception& e) {
                ++rejected;
                const std::string m = e.what();
                EXPECT_LE(m.size(), kMaxMessage) << f.path << " mutation " << k << ": " << m.substr(0, 200);
                EXPECT_EQ(m.find('\n'), std::string::npos) << f.path << " mutation " << k << ": " << m.substr(0, 200);
                EXPECT_FALSE(m.empty()) << f.path << " mutation " << k;
            }
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%d mutations of %zu files, %d rejected, %.1f s\n", cases, files.size(), rejected, seconds);
    EXPECT_GT(rejected, cases / 4);  // the mutations do reach the checks
    EXPECT_LT(seconds, 60.0);
}

}  // namespace
}  // namespace brume
