#include "render/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <random>
#include <string>
#include <system_error>

namespace brume {

namespace {

namespace fs = std::filesystem;

std::string os_reason(int err) { return std::generic_category().message(err); }

[[noreturn]] void fail_write(const fs::path& path, const std::string& reason) {
    throw FileWriteError("cannot write " + path.string() + ": " + reason);
}

// Owns the temporary file until it has been renamed into place; on any failure closes and removes it.
class TempFile {
public:
    TempFile(fs::path path, int fd) : path_(std::move(path)), fd_(fd) {}
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    ~TempFile() {
        if (fd_ >= 0) ::close(fd_);
        if (!committed_) ::unlink(path_.c_str());
    }
    int fd() const { return fd_; }
    const fs::path& path() const { return path_; }
    // Closing can report a delayed write error (NFS, quotas), so it is checked, not left to the destructor.
    int close() {
        const int r = ::close(fd_);
        fd_ = -1;
        return r;
    }
    void commit() { committed_ = true; }

private:
    fs::path path_;
    int fd_;
    bool committed_ = false;
};

// Creates a uniquely named file beside the target; the name starts with '.' so listings hide it.
TempFile create_temp_beside(const fs::path& path) {
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    // Keep the temporary name within NAME_MAX even when the target's name is already long.
    const std::string stem = path.filename().string().substr(0, 200);
    std::random_device random;
    for (int attempt = 0; attempt < 64; ++attempt) {
        char suffix[16];
        std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(random()));
        fs::path temp = dir / ("." + stem + ".tmp-" + suffix);
        // 0666 before the umask: the finished file gets the permissions of any newly created file.
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) return TempFile(std::move(temp), fd);
        if (errno != EEXIST) {
            const int err = errno;
            fail_write(path, "cannot create a temporary file in " + dir.string() + ": " + os_reason(err));
        }
    }
    fail_write(path, "cannot find a free temporary file name in " + dir.string());
}

}  // namespace

// Write, flush to disk, then rename: readers see either the old file or the complete new one.
void write_file_atomically(const fs::path& path, std::string_view bytes) {
    if (!path.has_filename()) fail_write(path, "not a file name");
    TempFile temp = create_temp_beside(path);
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(temp.fd(), bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            fail_write(path, "writing " + temp.path().string() + ": " + os_reason(err));
        }
        done += static_cast<std::size_t>(n);
    }
    // Without fsync a crash soon after the rename can leave an empty file where the old good one was.
    if (::fsync(temp.fd()) != 0) {
        const int err = errno;
        fail_write(path, "flushing " + temp.path().string() + ": " + os_reason(err));
    }
    if (temp.close() != 0) {
        const int err = errno;
        fail_write(path, "closing " + temp.path().string() + ": " + os_reason(err));
    }
    if (::rename(temp.path().c_str(), path.c_str()) != 0) {
        const int err = errno;
        fail_write(path, "renaming " + temp.path().string() + " into place: " + os_reason(err));
    }
    temp.commit();
}


void check_writable_path(const fs::path& path) {
    if (!path.has_filename()) fail_write(path, "not a file name");
    std::error_code ec;
    if (fs::is_directory(path, ec)) fail_write(path, "it is a directory");
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::exists(dir, ec)) fail_write(path, "directory " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec)) fail_write(path, dir.string() + " is not a directory");
    if (::access(dir.c_str(), W_OK) != 0) fail_write(path, "directory " + dir.string() + ": " + os_reason(errno));
}

}  // namespace brume
