// Image files: EXR keeps every float bit, PNG applies exposure and the exact sRGB curve, and a write that
// fails leaves neither a partial file nor a damaged old one (the contracts in README.md, "Tour").
#include "render/image_io.h"

#include <gtest/gtest.h>

#include <stb/stb_image.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace brume {
namespace {

namespace fs = std::filesystem;

class ImageIo : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("brume_image_io_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Names of everything in the test directory: catches leftover temporary files.
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    fs::path dir_;
};

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

Image noise_image(int w, int h, unsigned seed) {
    Image image(w, h);
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> u(0.0f, 4.0f);
    for (float& v : image.rgb) v = u(random);
    return image;
}

// A PNG decoded back through stb_image.
struct Decoded {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> bytes;
};

Decoded decode_png(const fs::path& path) {
    Decoded d;
    unsigned char* data = stbi_load(path.c_str(), &d.width, &d.height, &d.channels, 0);
    if (!data) return d;
    d.bytes.assign(data, data + std::size_t(d.width) * d.height * d.channels);
    stbi_image_free(data);
    return d;
}

// Writes one row whose pixels are grey at the given linear values, and decodes it.
Decoded png_of(const std::vector<float>& linear, const fs::path& path, double exposure = 0.0) {
    Image image(int(linear.size()), 1);
    for (std::size_t i = 0; i < linear.size(); ++i)
        for (int c = 0; c < 3; ++c) image.rgb[i * 3 + c] = linear[i];
    write_png(image, path, exposure);
    return decode_png(path);
}

// Pixel types of an EXR's channels, read from the header itself: 0 UINT, 1 HALF, 2 FLOAT.
std::map<std::string, int> exr_channel_types(const std::string& file) {
    std::map<std::string, int> types;
    std::size_t at = 8;  // magic and version
    const auto read_string = [&] {
        const std::size_t end = file.find('\0', at);
        std::string s = file.substr(at, end - at);
        at = end + 1;
        return s;
    };
    const auto read_int = [&] {
        std::int32_t v;
        std::memcpy(&v, file.data() + at, 4);
        at += 4;
        return v;
    };
    while (at < file.size()) {
        const std::string name = read_string();
        if (name.empty()) break;
        const std::string type = read_string();
        const std::int32_t size = read_int();
        if (name == "channels" && type == "chlist") {
            const std::size_t end = at + std::size_t(size);
            while (at < end) {
                const std::string channel = read_string();
                if (channel.empty()) break;
                types[channel] = read_int();
                at += 4 + 8;  // pLinear, reserved, x and y sampling
            }
            return types;
        }
        at += std::size_t(size);
    }
    return types;
}

TEST(SrgbEncode, ExactPiecewiseCurve) {
    EXPECT_EQ(srgb_encode(0.0f), 0.0f);
    EXPECT_NEAR(srgb_encode(1.0f), 1.0f, 1e-7);
    EXPECT_NEAR(srgb_encode(0.5f), 0.735356983f, 1e-7);
    EXPECT_NEAR(srgb_encode(0.001f), 0.01292f, 1e-9);     // linear toe
    EXPECT_NEAR(srgb_encode(0.18f), 0.461356129f, 1e-7);  // middle grey
    // The two pieces meet at the threshold (continuity within the standard's rounding).
    EXPECT_NEAR(srgb_encode(0.0031308f), 0.04045f, 1e-5);
    EXPECT_NEAR(srgb_encode(std::nextafter(0.0031308f, 1.0f)), 0.04045f, 1e-5);
}

TEST_F(ImageIo, ExrRoundTripIsBitExact) {
    const float awkward[] = {0.0f,
                             -0.0f,
                             1.0f,
                             0.1f,
                             -2.5f,
                             1e-30f,
                             std::numeric_limits<float>::min(),
                             std::numeric_limits<float>::denorm_min(),
                             3e38f,
                             std::numeric_limits<float>::max(),
                             -std::numeric_limits<float>::max(),
                             65504.0f,  // half's maximum: a half file would saturate just above it
                             65520.0f,
                             1.0f / 3.0f,
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN()};
    Image image = noise_image(7, 5, 1);
    for (std::size_t i = 0; i < std::size(awkward); ++i) image.rgb[i * 2] = awkward[i];
    const fs::path path = dir_ / "round.exr";
    write_exr(image, path);

    const Image back = read_exr(path);
    ASSERT_EQ(back.width, 7);
    ASSERT_EQ(back.height, 5);
    ASSERT_EQ(back.rgb.size(), image.rgb.size());
    EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
    EXPECT_EQ(back.pixel(6, 4)[2], image.pixel(6, 4)[2]);  // orientation: last pixel stays last

    const auto types = exr_channel_types(read_bytes(path));
    EXPECT_EQ(types, (std::map<std::string, int>{{"B", 2}, {"G", 2}, {"R", 2}}));  // FLOAT, not HALF
    EXPECT_EQ(listing(), std::vector<std::string>{"round.exr"});
}

TEST_F(ImageIo, PngEncodesKnownValues) {
    const Decoded d = png_of({0.0f, 1.0f, 0.5f, 0.25f, 2.0f, -1.0f, std::nanf(""),
                              std::numeric_limits<float>::infinity(), 0.001f},
                             dir_ / "known.png");
    ASSERT_EQ(d.width, 9);
    ASSERT_EQ(d.height, 1);
    ASSERT_EQ(d.channels, 3);
    // The undithered codes; the file holds them to within the dither's one code, exactly where black,
    // saturated, NaN and infinite values leave no room.
    const unsigned char expected[] = {0, 255, 188, 137, 255, 0, 0, 255, 3};
    const bool exact[] = {true, true, false, false, true, true, true, true, false};
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c) {
            const int got = int(d.bytes[i * 3 + c]);
            if (exact[i])
                EXPECT_EQ(got, int(expected[i])) << "pixel " << i;
            else
                EXPECT_LE(std::abs(got - int(expected[i])), 1) << "pixel " << i;
        }
}

TEST_F(ImageIo, PngChannelsAndRowsKeepTheirPlaces) {
    Image image(2, 2);
    const float values[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0}};
    for (int p = 0; p < 4; ++p)
        for (int c = 0; c < 3; ++c) image.pixel(p % 2, p / 2)[c] = values[p][c];
    write_png(image, dir_ / "layout.png");
    const Decoded d = decode_png(dir_ / "layout.png");
    ASSERT_EQ(d.bytes.size(), 12u);
    const unsigned char expected[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 188, 188, 0};
    for (int i = 0; i < 12; ++i) {
        // Byte i is pixel (i / 3 % 2, i / 6), channel i % 3: the dither of that place, exactly.
        const int p = i / 3;
        EXPECT_EQ(int(d.bytes[i]), int(png_code(values[p][i % 3], 1.0, png_dither(p % 2, p / 2, i % 3)))) << "byte " << i;
        EXPECT_LE(std::abs(int(d.bytes[i]) - int(expected[i])), 1) << "byte " << i;
    }
}

TEST_F(ImageIo, PngExposureScalesBeforeTheCurve) {
    // +1 stop doubles the linear value: 0.25 at +1 encodes as 0.5 does at 0.
    const std::vector<float> ramp = {0.0f, 0.001f, 0.01f, 0.05f, 0.1f, 0.2f, 0.25f, 0.3f, 0.4f, 0.5f};
    std::vector<float> doubled;
    for (float v : ramp) doubled.push_back(2.0f * v);
    const Decoded plus_one = png_of(ramp, dir_ / "plus_one.png", 1.0);
    const Decoded reference = png_of(doubled, dir_ / "doubled.png", 0.0);
    const Decoded unexposed = png_of(ramp, dir_ / "unexposed.png", 0.0);
    EXPECT_EQ(plus_one.bytes, reference.bytes);
    EXPECT_NE(plus_one.bytes, unexposed.bytes);
    EXPECT_EQ(int(plus_one.bytes[6 * 3]), int(png_code(0.5f, 1.0, png_dither(6, 0, 0))));  // 0.25 at +1
    EXPECT_EQ(int(png_of({1.0f}, dir_ / "minus_one.png", -1.0).bytes[0]), int(png_code(0.5f, 1.0, png_dither(0, 0, 0))));
}

TEST_F(ImageIo, PngMatchesTheCurveAcrossTheRange) {
    std::vector<float> ramp;
    for (int i = 0; i <= 1000; ++i) ramp.push_back(float(i) / 1000.0f);
    const Decoded d = png_of(ramp, dir_ / "ramp.png");
    ASSERT_EQ(d.bytes.size(), ramp.size() * 3);
    for (std::size_t i = 0; i < ramp.size(); ++i) {
        const double v = ramp[i];
        const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        EXPECT_EQ(int(d.bytes[i * 3]), int(std::floor(encoded * 255.0 + 0.5 + png_dither(int(i), 0, 0)))) << "linear " << v;
        EXPECT_LE(std::abs(int(d.bytes[i * 3]) - int(std::lround(encoded * 255.0))), 1) << "linear " << v;
    }
}

// A flat value a third of the way between two codes: undithered it is one code everywhere (a band);
// dithered, the codes around it mix so that their mean is the value, and the image stays deterministic.
TEST_F(ImageIo, PngDitherRemovesBanding) {
    const double target_code = 100.3;
    // Linear value whose encoding is 100.3 / 255: the sRGB curve inverted in double.
    const double e = target_code / 255.0;
    const float linear = float(std::pow((e + 0.055) / 1.055, 2.4));
    Image flat(128, 64);
    for (float& v : flat.rgb) v = linear;
    write_png(flat, dir_ / "flat.png");
    const Decoded d = decode_png(dir_ / "flat.png");
    double sum = 0.0;
    int low = 0, high = 0;
    for (const unsigned char b : d.bytes) {
        sum += b;
        low += b == 100;
        high += b == 101;
        ASSERT_TRUE(b == 100 || b == 101) << int(b);
    }
    const double mean = sum / double(d.bytes.size());
    EXPECT_NEAR(mean, target_code, 0.02);  // 24576 samples: the dither's mean error is about 0.003
    EXPECT_GT(low, 0);
    EXPECT_GT(high, 0);
    EXPECT_EQ(int(png_code(linear, 1.0)), 100) << "undithered, every pixel would be 100";
    write_png(flat, dir_ / "again.png");
    EXPECT_EQ(decode_png(dir_ / "again.png").bytes, d.bytes);
}

TEST_F(ImageIo, WritingIntoAMissingDirectoryThrowsAndLeavesNothing) {
    const fs::path missing = dir_ / "no_such_dir";
    const Image image = noise_image(4, 3, 2);
    for (const fs::path& path : {missing / "out.exr", missing / "out.png"}) {
        try {
            if (path.extension() == ".exr")
                write_exr(image, path);
            else
                write_png(image, path);
            ADD_FAILURE() << "wrote " << path;
        } catch (const ImageIoError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path.string()), std::string::npos) << what;
            EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
        }
    }
    EXPECT_FALSE(fs::exists(missing));
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIo, ReadingAMissingExrThrowsNamingIt) {
    const fs::path path = dir_ / "absent.exr";
    try {
        read_exr(path);
        FAIL() << "read a missing file";
    } catch (const ImageIoError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    std::ofstream(dir_ / "garbage.exr") << "not an exr file";
    EXPECT_THROW(read_exr(dir_ / "garbage.exr"), ImageIoError);
}

// Lowers this process's file size limit so writes fail part way, as a full disk would.
class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t bytes) {
        ok_ = ::getrlimit(RLIMIT_FSIZE, &old_) == 0;
        old_handler_ = std::signal(SIGXFSZ, SIG_IGN);  // get EFBIG instead of being killed
        rlimit lowered = old_;
        lowered.rlim_cur = bytes;
        ok_ = ok_ && ::setrlimit(RLIMIT_FSIZE, &lowered) == 0;
    }
    ~FileSizeLimit() {
        ::setrlimit(RLIMIT_FSIZE, &old_);
        std::signal(SIGXFSZ, old_handler_);
    }
    bool ok() const { return ok_; }

private:
    rlimit old_{};
    void (*old_handler_)(int) = nullptr;
    bool ok_ = false;
};

TEST_F(ImageIo, FailedWriteLeavesTheExistingFileIntact) {
    const Image small(2, 2);
    const Image large = noise_image(128, 128, 3);  // encodes to far more than the limit below
    for (const char* name : {"keep.exr", "keep.png"}) {
        SCOPED_TRACE(name);
        const fs::path path = dir_ / name;
        const bool exr = fs::path(name).extension() == ".exr";
        exr ? write_exr(small, path) : write_png(small, path);
        const std::string before = read_bytes(path);
        ASSERT_FALSE(before.empty());
        {
            const FileSizeLimit limit(4096);
            ASSERT_TRUE(limit.ok());
            try {
                exr ? write_exr(large, path) : write_png(large, path);
                ADD_FAILURE() << "the write succeeded despite the size limit";
            } catch (const ImageIoError& e) {
                EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
            }
        }
        EXPECT_EQ(read_bytes(path), before);
        // The same write succeeds once the limit is gone, and replaces the file.
        exr ? write_exr(large, path) : write_png(large, path);
        EXPECT_NE(read_bytes(path), before);
        fs::remove(path);
        EXPECT_TRUE(listing().empty());  // no temporary file left behind
    }
}

TEST_F(ImageIo, ATargetThatIsADirectoryIsAnError) {
    fs::create_directory(dir_ / "taken.png");
    EXPECT_THROW(write_png(noise_image(2, 2, 4), dir_ / "taken.png"), ImageIoError);
    EXPECT_TRUE(fs::is_directory(dir_ / "taken.png"));
    EXPECT_EQ(listing(), std::vector<std::string>{"taken.png"});
}

TEST_F(ImageIo, InconsistentImagesAreRejectedBeforeTouchingDisk) {
    Image bad(4, 4);
    bad.rgb.resize(5);
    EXPECT_THROW(write_exr(bad, dir_ / "bad.exr"), ImageIoError);
    EXPECT_THROW(write_png(bad, dir_ / "bad.png"), ImageIoError);
    EXPECT_THROW(write_png(Image(), dir_ / "empty.png"), ImageIoError);
    EXPECT_TRUE(listing().empty());
}

}  // namespace
}  // namespace brume
