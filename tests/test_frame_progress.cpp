// The progress line of a long frame (app/frame_progress.h): its text, that it shows on a terminal only
// (a pseudo-terminal here) and only after a second, and that it clears its line when the frame ends.
#include "app/frame_progress.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

namespace brume::app {
namespace {

TEST(FrameProgress, LineSaysTheShareTheTimeAndWhatIsLeft) {
    EXPECT_EQ(FrameProgress::line("reference", 0, 230400, 1.2), "reference: 0% of 230400 pixels, 1 s");
    EXPECT_EQ(FrameProgress::line("reference", 57600, 230400, 10.0),
              "reference: 25% of 230400 pixels, 10 s, about 30 s left");
    EXPECT_EQ(FrameProgress::line("r", 999, 1000, 20.0), "r: 99% of 1000 pixels, 20 s, about 0 s left");
}

// Everything written to the pseudo-terminal's other end so far (it is non-blocking).
std::string drain(int master) {
    std::string text;
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(master, buffer, sizeof buffer);
        if (n <= 0) break;
        text.append(buffer, std::size_t(n));
    }
    return text;
}

TEST(FrameProgress, ShowsOnATerminalAfterASecondAndClearsItsLine) {
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
    ASSERT_GE(master, 0);
    ASSERT_EQ(::grantpt(master), 0);
    ASSERT_EQ(::unlockpt(master), 0);
    std::FILE* terminal = std::fopen(::ptsname(master), "w");
    ASSERT_NE(terminal, nullptr);
    ASSERT_EQ(::fcntl(master, F_SETFL, O_NONBLOCK), 0);
    std::atomic<std::uint64_t> done{777};  // reset by the display
    {
        FrameProgress progress("reference", 1000, done, terminal);
        EXPECT_EQ(done.load(), 0u);
        done = 500;
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        EXPECT_EQ(drain(master), "");  // quiet within the first second
        std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    }
    const std::string shown = drain(master);
    // The seconds depend on when the display's thread woke (about 1 s, later on a loaded machine).
    const std::size_t at = shown.find("\rreference: 50% of 1000 pixels, ");
    ASSERT_NE(at, std::string::npos) << shown;
    EXPECT_NE(shown.find(" s left\033[K", at), std::string::npos) << shown;
    EXPECT_EQ(shown.substr(shown.size() - 4), "\r\033[K") << shown;  // the line cleared at the end
    std::fclose(terminal);
    ::close(master);
}

TEST(FrameProgress, SaysNothingWhereTheOutputIsNoTerminal) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    std::atomic<std::uint64_t> done{0};
    {
        FrameProgress progress("reference", 1000, done, file);
        done = 500;
        std::this_thread::sleep_for(std::chrono::milliseconds(1300));
    }
    EXPECT_EQ(std::ftell(file), 0L);
    std::fclose(file);
}

}  // namespace
}  // namespace brume::app
