// What the preview's window shows, read back from its swapchain (the script's `capture`), against the
// PNG `brume play` writes for the same frame: within one 8-bit code per channel, because the window's
// tone map runs on the GPU in float and the PNG writer on the CPU in double
// (tests/test_gpu_frame_path.cpp ToneMapMatchesThePngWriter bounds the same difference). With the panel
// on, the panel's pixels differ from the frame: the UI is drawn in the same pass. Runs `brume`
// (BRUME_EXECUTABLE) under the X server that ctest's xvfb-run provides, with validation on.
#include "render/image_io.h"

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Png {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
};

Png read_png(const fs::path& path) {
    Png png;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &channels, 3);
    if (data) {
        png.rgb.assign(data, data + std::size_t(png.width) * png.height * 3);
        stbi_image_free(data);
    }
    return png;
}

class WindowPreview : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
        const char* lavapipe = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
        setenv("VK_DRIVER_FILES", lavapipe, 1);
        setenv("VK_ICD_FILENAMES", lavapipe, 1);
        dir_ = fs::temp_directory_path() / ("brume_window_preview_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!HasFailure()) fs::remove_all(dir_);
    }
    // Runs `brume ARGS` in the scratch directory; its exit status.
    int brume(const std::string& args) {
        const std::string command = "cd '" + dir_.string() + "' && '" BRUME_EXECUTABLE "' " + args + " >>log.txt 2>&1";
        return std::system(command.c_str());
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    Png png(const std::string& name) { return read_png(dir_ / name); }

    fs::path dir_;
};

TEST_F(WindowPreview, WindowShowsWhatPlayWritesWithinOneCode) {
    ASSERT_EQ(brume("play crossing -o play --frames 7-7 --size 96x72 --format png"), 0);
    write("window.script", "panel off\nframe 7\nwait 2\ncapture window.png\nquit\n");
    ASSERT_EQ(brume("preview crossing --size 96x72 --validate --script window.script"), 0) << dir_ / "log.txt";
    const Png want = png("play/crossing.0007.png");
    const Png got = png("window.png");
    ASSERT_EQ(got.width, 96);
    ASSERT_EQ(got.height, 72);
    ASSERT_EQ(want.rgb.size(), got.rgb.size());
    // PNG files are dithered (+-0.5 code before rounding) and the window is not, so a channel may
    // differ by one code, never more, and on average they agree to well under a code (measured: 0.16
    // on this frame; a wrong exposure or transfer curve is off by several).
    int worst = 0;
    long long signed_sum = 0;
    std::size_t lit = 0;
    for (std::size_t i = 0; i < want.rgb.size(); ++i) {
        const int d = int(want.rgb[i]) - int(got.rgb[i]);
        worst = std::max(worst, std::abs(d));
        signed_sum += d;
        lit += want.rgb[i] > 20;
    }
    EXPECT_LE(worst, 1);
    EXPECT_LT(std::abs(double(signed_sum) / double(want.rgb.size())), 0.3);
    EXPECT_GT(lit, want.rgb.size() / 10);  // not a black frame: the comparison means something
}

TEST_F(WindowPreview, PanelIsDrawnOverTheFrameAndScreenshotsLeaveItOut) {
    write("panel.script", "wait 2\ncapture window.png\nscreenshot shot.png\nquit\n");
    ASSERT_EQ(brume("preview plume --size 480x360 --validate --script panel.script"), 0) << dir_ / "log.txt";
    const Png window = png("window.png");
    const Png shot = png("shot.png");
    ASSERT_EQ(window.rgb.size(), shot.rgb.size());
    ASSERT_EQ(window.width, 480);
    // The panel sits at the top left: most pixels there differ by far more than the tone map's one code.
    std::size_t panel_px = 0, differ = 0;
    for (int y = 10; y < 100; ++y)
        for (int x = 10; x < 150; ++x) {
            ++panel_px;
            const std::size_t i = (std::size_t(y) * 480 + x) * 3;
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(window.rgb[i + c]) - int(shot.rgb[i + c])));
            differ += d > 8;
        }
    EXPECT_GT(differ, panel_px / 2);
    // Right of the panel (340 pixels wide) is frame only.
    int worst = 0;
    for (int y = 300; y < 360; ++y)
        for (int x = 400; x < 480; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (std::size_t(y) * 480 + x) * 3 + c;
                worst = std::max(worst, std::abs(int(window.rgb[i]) - int(shot.rgb[i])));
            }
    EXPECT_LE(worst, 1);
}

// The split view is the method's frame left of the middle column and the other's right of it; the
// difference view is |method - other| x 8; both exactly, read from the linear EXR screenshots.
TEST_F(WindowPreview, SplitAndDifferenceViewsComposeTheTwoMethods) {
    write("compare.script",
          "frame 8\nmethod ppll\nwait 1\nscreenshot ppll.exr\nmethod soft\nscreenshot soft.exr\nmethod ppll\n"
          "compare soft split\nwait 1\nscreenshot split.exr\ncompare soft difference\nwait 1\n"
          "screenshot difference.exr\ncompare off\nwait 1\nscreenshot again.exr\nquit\n");
    ASSERT_EQ(brume("preview crossing --size 96x72 --validate --script compare.script"), 0) << dir_ / "log.txt";
    const brume::Image a = brume::read_exr(dir_ / "ppll.exr");
    const brume::Image b = brume::read_exr(dir_ / "soft.exr");
    const brume::Image split = brume::read_exr(dir_ / "split.exr");
    const brume::Image difference = brume::read_exr(dir_ / "difference.exr");
    const brume::Image again = brume::read_exr(dir_ / "again.exr");
    ASSERT_EQ(a.width, 96);
    ASSERT_EQ(split.rgb.size(), a.rgb.size());
    ASSERT_EQ(difference.rgb.size(), a.rgb.size());
    EXPECT_EQ(again.rgb, a.rgb);  // off: the method alone again
    int differing = 0, split_bad = 0, difference_bad = 0;
    for (int j = 0; j < 72; ++j)
        for (int i = 0; i < 96; ++i)
            for (int c = 0; c < 3; ++c) {
                const float va = a.pixel(i, j)[c], vb = b.pixel(i, j)[c];
                differing += va != vb;
                const float want_split = i < 48 ? va : i == 48 ? 1.0f : vb;
                split_bad += split.pixel(i, j)[c] != want_split;
                difference_bad += difference.pixel(i, j)[c] != std::abs(va - vb) * 8.0f;
            }
    EXPECT_GT(differing, 100);  // the methods disagree somewhere, so the halves are told apart
    EXPECT_EQ(split_bad, 0);
    EXPECT_EQ(difference_bad, 0);
}

}  // namespace

// The heat map of list length tints exactly the pixels whose ray meets a sphere (the count the
// screenshot line reports, from the heat-map pass) and leaves every other pixel as the frame has it;
// off again, the frame is the method's alone. Read from the linear EXR screenshots.
TEST_F(WindowPreview, HeatMapTintsExactlyThePixelsWithLists) {
    write("heat.script",
          "frame 8\nwait 1\nscreenshot plain.exr\nheat-map on\nwait 1\nscreenshot heat.exr\nheat-map off\nwait 1\n"
          "screenshot off.exr\nheat-map on\nwait 1\nquit\n");
    // Quitting with the overlay shown: its composite must outlive the last frame that samples it
    // (validation would fail the run, status 3).
    ASSERT_EQ(brume("preview crossing --size 96x72 --validate --script heat.script"), 0) << dir_ / "log.txt";
    const brume::Image plain = brume::read_exr(dir_ / "plain.exr");
    const brume::Image heat = brume::read_exr(dir_ / "heat.exr");
    const brume::Image off = brume::read_exr(dir_ / "off.exr");
    ASSERT_EQ(plain.width, 96);
    ASSERT_EQ(heat.rgb.size(), plain.rgb.size());
    EXPECT_EQ(off.rgb, plain.rgb);
    std::ifstream log(dir_ / "log.txt");
    unsigned long long with_lists = 0, nodes = 0;
    double longest = 0.0, mean = 0.0;
    bool found = false;
    for (std::string line; std::getline(log, line);) {
        const std::size_t at = line.find(", heat map: ");
        if (line.rfind("screenshot heat.exr", 0) == 0 && at != std::string::npos)
            found = std::sscanf(line.c_str() + at, ", heat map: longest %lf, mean %lf over %llu pixels, %llu nodes",
                                &longest, &mean, &with_lists, &nodes) == 4;
    }
    ASSERT_TRUE(found) << "no heat map figures in " << dir_ / "log.txt";
    std::size_t tinted = 0;
    for (std::size_t p = 0; p < plain.rgb.size() / 3; ++p) {
        bool differs = false;
        for (int c = 0; c < 3; ++c) differs = differs || heat.rgb[p * 3 + c] != plain.rgb[p * 3 + c];
        tinted += differs;
    }
    EXPECT_EQ(tinted, with_lists);
    EXPECT_GT(with_lists, 96u * 72u / 20u);  // the jets cover part of the view ...
    EXPECT_LT(with_lists, 96u * 72u);        // ... not all of it
    EXPECT_GE(longest, 2.0);                 // they overlap
    EXPECT_NEAR(mean * double(with_lists), double(nodes), 0.5);
}
