// A bounded, seeded fuzz run of the scene and preset readers (issue 14, "Tests"): mutations of every
// shipped preset and test scene (byte flips, truncation, deep nesting, huge numbers, long strings,
// wrong types). Every mutation must parse or fail with one std::exception whose message is a
// single line of bounded length; a crash, a hang (ctest's timeout) or anything else fails the test.
// tests/cli_errors.sh runs a sample of such files through the brume binary, where a failed run must
// also leave an existing output byte-identical.
#include "sim/preset_file.h"
#include "sim/scene_file.h"
#include "fuzz_mutations.h"

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

TEST(FuzzInputs, EveryMutationParsesOrFailsWithOneBoundedLine) {
    const std::vector<fuzz::Input> files = fuzz::inputs(BRUME_SOURCE_DIR);
    ASSERT_GE(files.size(), 10u) << "the shipped presets and test scenes were not found under " << BRUME_SOURCE_DIR;
    std::mt19937_64 rng(20261202);  // seeded: a failure reproduces
    const auto start = std::chrono::steady_clock::now();
    int cases = 0, rejected = 0;
    for (const fuzz::Input& f : files) {
        const std::string original = read(f.path);
        for (int k = 0; k < 300; ++k) {
            const std::string text = fuzz::mutate(original, rng);
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
