#include "render/atomic_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <random>
#include <string>
#include <system_error>
#include <utility>

namespace brume {

namespace {

namespace fs = std::filesystem;

std::string os_reason(int err) { return std::generic_category().message(err); }

[[noreturn]] void fail_write(const fs::path& path, const std::string& reason) {
    throw FileWriteError("cannot write " + path.string() + ": " + reason);
}

fs::path directory_of(const fs::path& path) { return path.has_parent_path() ? path.parent_path() : fs::path("."); }

// The prefix of every temporary file for `target`; the name starts with '.' so listings hide it,
// and the target's name is cut so that the whole name stays within NAME_MAX (200 of its bytes at
// most), and the whole path, as open() and link() are handed it, within PATH_MAX: a temporary's path
// is up to 18 bytes longer than its target's, so a target within that of PATH_MAX could not be
// written ("File name too long"). Only such a target's prefix is shorter; the cleaner
// (remove_stale_temporaries) computes the same one.
// (Appended, not "." + std::string&&: GCC 12 warns on that, -Wrestrict, a false positive.)
std::string temp_prefix(const fs::path& target) {
    // Around the kept part of the name: the directory and its separator, '.', ".tmp-", the
    // 8-character tag, the longest suffix (".old") and the terminating NUL.
    const std::size_t around = directory_of(target).native().size() + 1 + 1 + 5 + 8 + 4 + 1;
    const std::size_t room = around < std::size_t(PATH_MAX) ? std::size_t(PATH_MAX) - around : 0;
    std::string prefix = ".";
    prefix.append(target.filename().string(), 0, std::min<std::size_t>(200, room)).append(".tmp-");
    return prefix;
}

bool same_file(const struct stat& a, const struct stat& b) { return a.st_dev == b.st_dev && a.st_ino == b.st_ino; }

// Writes all of `bytes` to `fd`, retrying short writes and EINTR; returns 0 or the errno.
int write_all(int fd, std::string_view bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

int standard_output_fd = STDOUT_FILENO;

}  // namespace

bool names_standard_output(const fs::path& path) { return path.native() == kStandardOutputName; }

void set_standard_output_descriptor(int fd) { standard_output_fd = fd; }

int standard_output_descriptor() { return standard_output_fd; }

OutputTarget resolve_output(const fs::path& path) {
    if (path.empty()) fail_write(path, "an empty file name");
    if (names_standard_output(path)) return {path, true, standard_output_fd};
    // stat follows every link, /proc's fd links included, to what a write would reach.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISREG(st.st_mode)) {
            std::error_code ec;
            const fs::path real = fs::canonical(path, ec);  // the temporary file goes beside the real file
            return {ec ? path : real, false};
        }
        if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return {path, true};
        const std::string what = S_ISDIR(st.st_mode)    ? "a directory"
                                 : S_ISBLK(st.st_mode)  ? "a block device"
                                 : S_ISSOCK(st.st_mode) ? "a socket"
                                                        : "not a regular file";
        fail_write(path, "it is " + what + " (Brume replaces only regular files and writes into character devices and FIFOs)");
    }
    if (errno != ENOENT) {
        const int err = errno;
        fail_write(path, os_reason(err));
    }
    // Nothing there, or a link to a name not made yet: follow the links to the name to create.
    fs::path p = path;
    for (int hops = 0;; ++hops) {
        if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return {p, false};
        if (hops >= 40) fail_write(path, "too many levels of symbolic links");
        std::error_code ec;
        const fs::path next = fs::read_symlink(p, ec);
        if (ec) fail_write(path, "reading the symbolic link " + p.string() + ": " + ec.message());
        p = next.is_absolute() ? next : directory_of(p) / next;
    }
}

void remove_stale_temporaries(const fs::path& path) {
    const fs::path target = resolve_output(path).path;
    const std::string prefix = temp_prefix(target);
    const fs::path dir = directory_of(target);
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const fs::path entry = it->path();
        if (entry.filename().string().rfind(prefix, 0) != 0) continue;
        // A writer holds its temporary file's lock until it renames the file or dies (the kernel
        // drops the locks of a killed process), so a lock we can take means nobody will finish it.
        const int fd = ::open(entry.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
        if (fd < 0) continue;
        struct stat held {}, named {};
        if (::fstat(fd, &held) == 0 && S_ISREG(held.st_mode) && ::flock(fd, LOCK_EX | LOCK_NB) == 0 &&
            ::lstat(entry.c_str(), &named) == 0 && same_file(held, named))
            ::unlink(entry.c_str());
        ::close(fd);
    }
}

int create_locked_temporary(const fs::path& path, const std::string& suffix, fs::path& temp) {
    const fs::path target = resolve_output(path).path;
    const fs::path dir = directory_of(target);
    std::random_device random;
    for (int attempt = 0; attempt < 64; ++attempt) {
        char tag[16];
        std::snprintf(tag, sizeof tag, "%08x", static_cast<unsigned>(random()));
        fs::path name = dir / (temp_prefix(target) + tag + suffix);
        // 0666 before the umask: the finished file gets the permissions of any newly created file.
        const int fd = ::open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            if (errno == EEXIST) continue;
            const int err = errno;
            fail_write(path, "cannot create a temporary file in " + dir.string() + ": " + os_reason(err));
        }
        // A cleaner could have taken the name between open and flock and removed it: then the name
        // no longer leads to this file, and another is made.
        struct stat held {}, named {};
        if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &held) == 0 && ::lstat(name.c_str(), &named) == 0 &&
            same_file(held, named)) {
            temp = std::move(name);
            return fd;
        }
        ::close(fd);
    }
    fail_write(path, "cannot find a free temporary file name in " + dir.string());
}

fs::path link_old_file(const fs::path& target) {
    struct stat st {};
    if (::lstat(target.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
    std::random_device random;
    for (int attempt = 0; attempt < 64; ++attempt) {
        char tag[16];
        std::snprintf(tag, sizeof tag, "%08x", static_cast<unsigned>(random()));
        fs::path name = directory_of(target) / (temp_prefix(target) + tag + ".old");
        if (::link(target.c_str(), name.c_str()) == 0) return name;
        if (errno != EEXIST) return {};
    }
    return {};
}

StagedFile::StagedFile(const fs::path& path, std::string_view bytes) : path_(path) {
    if (!path.has_filename()) fail_write(path, "not a file name");
    target_ = resolve_output(path);
    if (target_.in_place) {  // a device or FIFO cannot be replaced, so the bytes wait for commit()
        held_.assign(bytes);
        return;
    }
    remove_stale_temporaries(path);
    fd_ = create_locked_temporary(path, "", temp_);
    // A constructor that throws runs no destructor: the temporary file is removed here.
    try {
        // A replaced file keeps its permissions (a group-writable output stays group-writable).
        struct stat old {};
        if (::stat(target_.path.c_str(), &old) == 0 && S_ISREG(old.st_mode)) (void)::fchmod(fd_, old.st_mode & 07777);
        if (const int err = write_all(fd_, bytes)) fail_write(path, "writing " + temp_.string() + ": " + os_reason(err));
        // Without fsync a crash soon after the rename can leave an empty file where the old good one was.
        if (::fsync(fd_) != 0) {
            const int err = errno;
            fail_write(path, "flushing " + temp_.string() + ": " + os_reason(err));
        }
    } catch (...) {
        ::unlink(temp_.c_str());
        ::close(fd_);
        throw;
    }
}

StagedFile::StagedFile(StagedFile&& other) noexcept
    : path_(std::move(other.path_)),
      target_(std::move(other.target_)),
      temp_(std::exchange(other.temp_, fs::path())),
      held_(std::move(other.held_)),
      fd_(std::exchange(other.fd_, -1)) {}

StagedFile::~StagedFile() {
    if (!temp_.empty()) ::unlink(temp_.c_str());
    if (fd_ >= 0) ::close(fd_);
}

void StagedFile::commit() {
    if (target_.descriptor >= 0) {
        if (const int err = write_all(target_.descriptor, held_))
            throw FileWriteError("cannot write to standard output: " + os_reason(err));
        return;
    }
    if (target_.in_place) {
        const int fd = ::open(target_.path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (fd < 0) {
            const int err = errno;
            fail_write(path_, os_reason(err));
        }
        const int err = write_all(fd, held_);
        ::close(fd);
        if (err) fail_write(path_, os_reason(err));
        return;
    }
    if (temp_.empty()) return;  // committed already
    if (::rename(temp_.c_str(), target_.path.c_str()) != 0) {
        const int err = errno;
        fail_write(path_, "renaming " + temp_.string() + " into place: " + os_reason(err));
    }
    temp_.clear();
    // Closing can report a delayed write error (NFS, quotas); the data was flushed by fsync already,
    // and closing last keeps the lock until the name is gone.
    ::close(std::exchange(fd_, -1));
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
    StagedFile staged(path, bytes);
    staged.commit();
}

void check_writable_path(const fs::path& path) {
    if (!path.has_filename()) fail_write(path, "not a file name");
    const OutputTarget target = resolve_output(path);
    if (target.descriptor >= 0) {
        const int flags = ::fcntl(target.descriptor, F_GETFL);
        if (flags < 0) throw FileWriteError("cannot write to standard output: it is closed");
        if ((flags & O_ACCMODE) == O_RDONLY) throw FileWriteError("cannot write to standard output: it is open for reading only");
        return;
    }
    if (target.in_place) {
        if (::access(target.path.c_str(), W_OK) != 0) fail_write(path, os_reason(errno));
        return;
    }
    std::error_code ec;
    const fs::path dir = directory_of(target.path);
    if (!fs::exists(dir, ec)) fail_write(path, "directory " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec)) fail_write(path, dir.string() + " is not a directory");
    if (::access(dir.c_str(), W_OK) != 0) fail_write(path, "directory " + dir.string() + ": " + os_reason(errno));
}

void check_writable_directory(const fs::path& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) throw FileWriteError("cannot write into " + dir.string() + ": it does not exist");
    if (!fs::is_directory(dir, ec)) throw FileWriteError("cannot write into " + dir.string() + ": not a directory");
    // Creating a file needs both: write to add the name, search to reach it.
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw FileWriteError("cannot write into directory " + dir.string() + ": " + os_reason(errno));
}

}  // namespace brume
