// Writing outputs never replaces what is not a regular file, follows links to the file they name,
// cleans up after killed runs and commits a run's outputs together (issue 14 items 10, 12, 13).
#include "render/atomic_file.h"
#include "render/output_set.h"
#include "tests/scratch_dir.h"

#include <gtest/gtest.h>

#include <sys/file.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <string>

namespace brume {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public testing::ScratchDir {
protected:
    static std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }
    static void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
    // Every name in the directory, hidden ones included, sorted.
    std::string listing() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        std::string out;
        for (const auto& n : names) out += n + " ";
        return out;
    }
};

TEST_F(AtomicFile, FollowsASymlinkAndKeepsIt) {
    put(dir_ / "real.txt", "old");
    fs::create_symlink("real.txt", dir_ / "link.txt");
    write_file_atomically(dir_ / "link.txt", "new");
    EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
    EXPECT_EQ(read(dir_ / "real.txt"), "new");
    EXPECT_EQ(listing(), "link.txt real.txt ");
}

TEST_F(AtomicFile, ADanglingSymlinkCreatesTheFileItNames) {
    fs::create_directories(dir_ / "sub");
    fs::create_symlink("sub/made.txt", dir_ / "link.txt");
    write_file_atomically(dir_ / "link.txt", "bytes");
    EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
    EXPECT_EQ(read(dir_ / "sub" / "made.txt"), "bytes");
}

TEST_F(AtomicFile, WritesIntoAFifoWithoutReplacingIt) {
    const fs::path fifo = dir_ / "pipe.exr";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto reader = std::async(std::launch::async, [&] { return read(fifo); });
    write_file_atomically(fifo, "through the pipe");
    EXPECT_EQ(reader.get(), "through the pipe");
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_EQ(listing(), "pipe.exr ");
}

TEST_F(AtomicFile, WritesIntoACharacterDevice) {
    // The old rename would have needed a temporary file in /dev (refused to a user, a replaced
    // /dev/null for root).
    EXPECT_NO_THROW(write_file_atomically("/dev/null", "discarded"));
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    EXPECT_TRUE(resolve_output("/dev/null").in_place);
}

TEST_F(AtomicFile, RefusesToReplaceADirectoryOrASocket) {
    fs::create_directories(dir_ / "d");
    EXPECT_THROW(write_file_atomically(dir_ / "d", "x"), FileWriteError);
    EXPECT_THROW(check_writable_path(dir_ / "d"), FileWriteError);
    const fs::path sock = dir_ / "s";
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    ASSERT_LT(sock.string().size(), sizeof addr.sun_path);
    std::strcpy(addr.sun_path, sock.c_str());
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    try {
        write_file_atomically(sock, "x");
        ADD_FAILURE() << "a socket was replaced";
    } catch (const FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find("a socket"), std::string::npos) << e.what();
    }
    EXPECT_THROW(check_writable_path(sock), FileWriteError);
    ::close(fd);
    EXPECT_TRUE(fs::is_socket(sock));
    EXPECT_TRUE(fs::is_directory(dir_ / "d"));
}

// `play` checks its output folder before the first frame. The check once asked whether a made-up
// file "probe" in it could be written, and so refused any folder that held a directory of that name.
TEST_F(AtomicFile, ADirectoryIsWritableWhateverNamesItHolds) {
    fs::create_directories(dir_ / "probe");
    fs::create_directories(dir_ / "d");
    put(dir_ / "plume.0000.png", "x");
    EXPECT_NO_THROW(check_writable_directory(dir_));
    put(dir_ / "f", "x");
    try {
        check_writable_directory(dir_ / "f");
        ADD_FAILURE() << "a regular file passed as a directory";
    } catch (const FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find("not a directory"), std::string::npos) << e.what();
    }
    try {
        check_writable_directory(dir_ / "missing");
        ADD_FAILURE() << "a missing directory passed";
    } catch (const FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    // A folder this process may not write into (root may write anywhere, so only as another user).
    if (::geteuid() != 0) {
        fs::permissions(dir_ / "d", fs::perms::owner_read | fs::perms::owner_exec);
        EXPECT_THROW(check_writable_directory(dir_ / "d"), FileWriteError);
        fs::permissions(dir_ / "d", fs::perms::owner_all);
    }
    EXPECT_EQ(listing(), "d f plume.0000.png probe ");  // nothing created, nothing removed
}

TEST_F(AtomicFile, RemovesTemporariesOfKilledRunsButNotOfLiveOnes) {
    put(dir_ / "out.exr", "old");
    put(dir_ / ".out.exr.tmp-0badf00d", "left by a killed run");  // nobody holds its lock
    put(dir_ / ".other.exr.tmp-12345678", "another output's");    // not this output's
    const fs::path live = dir_ / ".out.exr.tmp-1234abcd";
    put(live, "being written");
    const int fd = ::open(live.c_str(), O_RDONLY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX), 0);  // as a running writer holds it
    write_file_atomically(dir_ / "out.exr", "new");
    EXPECT_EQ(read(dir_ / "out.exr"), "new");
    EXPECT_FALSE(fs::exists(dir_ / ".out.exr.tmp-0badf00d"));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(dir_ / ".other.exr.tmp-12345678"));
    ::close(fd);
}

TEST_F(AtomicFile, KeepsTheReplacedFilesPermissions) {
    put(dir_ / "shared.txt", "old");
    fs::permissions(dir_ / "shared.txt", fs::perms(0664));
    write_file_atomically(dir_ / "shared.txt", "new");
    EXPECT_EQ(fs::status(dir_ / "shared.txt").permissions() & fs::perms::all, fs::perms(0664));
}

TEST_F(AtomicFile, AFailedOutputSetReplacesNothing) {
    put(dir_ / "a.exr", "old a");
    put(dir_ / "b.png", "old b");
    {
        OutputSet set;
        set.stage(dir_ / "a.exr", "new a");
        set.stage(dir_ / "b.png", "new b");
        EXPECT_THROW(set.stage(dir_ / "missing" / "c.json", "new c"), FileWriteError);
        // Not committed: the destructor removes the staged temporaries.
    }
    EXPECT_EQ(read(dir_ / "a.exr"), "old a");
    EXPECT_EQ(read(dir_ / "b.png"), "old b");
    EXPECT_EQ(listing(), "a.exr b.png ");
}

TEST_F(AtomicFile, ACommittedOutputSetReplacesEverything) {
    put(dir_ / "a.exr", "old a");
    OutputSet set;
    set.stage(dir_ / "a.exr", "new a");
    set.stage(dir_ / "b.png", "new b");
    EXPECT_EQ(read(dir_ / "a.exr"), "old a");  // staged, not yet visible
    set.commit();
    EXPECT_EQ(read(dir_ / "a.exr"), "new a");
    EXPECT_EQ(read(dir_ / "b.png"), "new b");
    EXPECT_EQ(listing(), "a.exr b.png ");
}

// "-" is standard output: its bytes go into the descriptor given, at commit and after the set's
// files are in place, and no file called "-" is made; "./-" is a file of that name.
TEST_F(AtomicFile, DashIsStandardOutputAndDotSlashDashAFile) {
    int pipe_fds[2];
    ASSERT_EQ(::pipe(pipe_fds), 0);
    set_standard_output_descriptor(pipe_fds[1]);
    const fs::path previous = fs::current_path();
    fs::current_path(dir_);
    EXPECT_TRUE(names_standard_output("-"));
    EXPECT_FALSE(names_standard_output("./-"));
    EXPECT_FALSE(names_standard_output("--"));
    check_writable_path("-");
    {
        OutputSet set;
        set.stage("-", "on the stream");
        set.stage(dir_ / "file.txt", "in the file");
        char byte = 0;
        EXPECT_EQ(::fcntl(pipe_fds[0], F_SETFL, O_NONBLOCK), 0);
        EXPECT_EQ(::read(pipe_fds[0], &byte, 1), -1) << "staged bytes reached the stream before the commit";
        set.commit();
    }
    char got[64] = {};
    EXPECT_EQ(::read(pipe_fds[0], got, sizeof got), ssize_t(std::strlen("on the stream")));
    EXPECT_STREQ(got, "on the stream");
    EXPECT_EQ(read(dir_ / "file.txt"), "in the file");
    write_file_atomically("./-", "a file called -");
    EXPECT_EQ(read(dir_ / "-"), "a file called -");
    EXPECT_EQ(listing(), "- file.txt ");
    // A closed standard output is refused by the check, and by the write with a message that names it.
    ::close(pipe_fds[1]);
    ::close(pipe_fds[0]);
    EXPECT_THROW(check_writable_path("-"), FileWriteError);
    try {
        write_file_atomically("-", "lost");
        ADD_FAILURE() << "no FileWriteError for a closed standard output";
    } catch (const FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find("standard output"), std::string::npos) << e.what();
    }
    set_standard_output_descriptor(STDOUT_FILENO);
    fs::current_path(previous);
}

TEST_F(AtomicFile, AFailedRenamePutsBackWhatTheSetReplaced) {
    put(dir_ / "a.exr", "old a");
    OutputSet set;
    set.stage(dir_ / "a.exr", "new a");
    set.stage(dir_ / "new.json", "new json");
    set.stage(dir_ / "b.png", "new b");
    // After staging, something no rename may replace appears at the last target.
    fs::create_directories(dir_ / "b.png" / "inside");
    EXPECT_THROW(set.commit(), FileWriteError);
    EXPECT_EQ(read(dir_ / "a.exr"), "old a");
    EXPECT_FALSE(fs::exists(dir_ / "new.json"));
    fs::remove_all(dir_ / "b.png");
    EXPECT_EQ(listing(), "a.exr ");
}

}  // namespace
}  // namespace brume
