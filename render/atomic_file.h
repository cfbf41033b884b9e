// Replacing a file so that no failure or interruption loses what was there: every output Brume
// writes (images, statistics, scenes) goes through here.
//
// What stands at an output path decides how it is written (issue 14 item 10):
// - nothing, or a regular file: a temporary file beside it, flushed, then renamed over it;
// - a symbolic link: followed to the file it names, which is then replaced as above (the link stays);
// - a character device or a FIFO (/dev/null, /dev/stdout, a pipe): written straight into;
// - anything else (a directory, a block device, a socket): refused, never replaced;
// - "-", exactly: standard output, as in most command-line tools (a file called "-" is ./-). Its bytes
//   wait for commit() and then go into the descriptor set_standard_output_descriptor gave (1 until then).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace brume {

class FileWriteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Where the bytes for an output path go.
struct OutputTarget {
    std::filesystem::path path;  // the path given, or the regular file its symlinks lead to
    bool in_place = false;       // a character device or FIFO: written into, never replaced
    int descriptor = -1;         // standard output ("-"): written into this open descriptor
};

// The name that stands for standard output.
inline constexpr const char* kStandardOutputName = "-";
bool names_standard_output(const std::filesystem::path& path);
// Where the bytes of an output named "-" go: a command that sends its own lines elsewhere to keep
// standard output for one output's bytes (app/standard_streams.h) gives the descriptor it kept.
void set_standard_output_descriptor(int fd);
// The descriptor an output named "-" is written into: the process's standard output as it was given.
int standard_output_descriptor();

// Follows symbolic links at `path` to what they name (at most 40, as the kernel allows). Throws
// FileWriteError naming `path` when it is, or leads to, something that must not be replaced.
OutputTarget resolve_output(const std::filesystem::path& path);

// The bytes of one output, written and flushed to a locked hidden temporary file beside its target
// (or held in memory for a device), not yet visible at the path. The destructor removes the
// temporary file unless commit() put it in place; a process killed outright leaves it behind, locked
// only while that process lived, and the next write to the same path removes it.
class StagedFile {
public:
    // Throws FileWriteError naming the path and the operating system's reason (a full disk here).
    StagedFile(const std::filesystem::path& path, std::string_view bytes);
    StagedFile(StagedFile&& other) noexcept;
    StagedFile& operator=(StagedFile&&) = delete;
    StagedFile(const StagedFile&) = delete;
    ~StagedFile();

    // Renames the temporary file over the target (or writes the held bytes into the device). Throws
    // FileWriteError; the old file is then still in place.
    void commit();
    const std::filesystem::path& path() const { return path_; }
    const OutputTarget& target() const { return target_; }

private:
    std::filesystem::path path_;  // as given, for messages
    OutputTarget target_;
    std::filesystem::path temp_;  // empty once committed or for in-place targets
    std::string held_;            // the bytes for an in-place target
    int fd_ = -1;                 // the temporary file, open and locked until commit
};

// Stages `bytes` for `path` and commits them at once: readers see either the old file or the
// complete new one, never a partial one. Throws FileWriteError naming the path and the reason.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Checks that `path` could be written (its directory exists and is a directory, the path is not a
// directory or anything else resolve_output refuses) without touching anything, so a command can
// refuse before it writes its first output. Throws FileWriteError naming the path.
void check_writable_path(const std::filesystem::path& path);

// Checks that files could be created in `dir`, an existing directory (it is one, and this process
// may write into it), without touching anything: for a command whose outputs' names come later
// (`play`'s frames). Not check_writable_path(dir / "some-name"), which refuses where that name
// happens to be a directory. Throws FileWriteError naming the directory.
void check_writable_directory(const std::filesystem::path& dir);

// Removes the temporary files that killed runs left beside `path` (".NAME.tmp-*" whose writer no
// longer holds its lock). Called by every StagedFile; exposed for the video encoder's temporary.
void remove_stale_temporaries(const std::filesystem::path& path);

// A second name for the regular file at `target` (a hard link, hidden and named like a temporary
// file, so a killed run's is removed like one), or empty when there is no such file or the
// filesystem refuses hard links. OutputSet renames it back when a later output of the set fails.
std::filesystem::path link_old_file(const std::filesystem::path& target);

// Creates a hidden, locked, empty temporary file beside `path` (its name ends in `suffix`) and
// returns its open descriptor; `temp` receives its path. For outputs another program writes (ffmpeg):
// while the descriptor stays open, remove_stale_temporaries leaves the file alone.
int create_locked_temporary(const std::filesystem::path& path, const std::string& suffix, std::filesystem::path& temp);

}  // namespace brume
