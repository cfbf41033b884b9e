#include "app/standard_streams.h"

#include "app/cli_util.h"
#include "render/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <system_error>

namespace brume::app {

void claim_standard_output(const std::string& option, bool binary) {
    check_writable_path(kStandardOutputName);  // closed, or open for reading only: refused here
    // Image bytes on a terminal are noise at best and can set its modes at worst; text is fine there.
    if (binary && ::isatty(STDOUT_FILENO))
        throw UsageError(option + " -: standard output is a terminal; redirect it to a file or a program "
                                  "(> FILE, | PROGRAM), or name a file");
    std::fflush(stdout);
    const int kept = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (kept < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0)
        throw FileWriteError("cannot write to standard output: " + std::generic_category().message(errno));
    // What the command prints now shares standard error with its error lines: line by line, so that
    // the two keep their order however standard error is redirected.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    set_standard_output_descriptor(kept);
}

std::string standard_output_alias(const std::string& path) {
    if (path.empty() || names_standard_output(path)) return path;
    struct stat out {}, named {};
    if (::fstat(STDOUT_FILENO, &out) != 0 || ::stat(path.c_str(), &named) != 0) return path;
    const bool stream_or_file = S_ISFIFO(out.st_mode) || S_ISSOCK(out.st_mode) || S_ISREG(out.st_mode);
    return stream_or_file && out.st_dev == named.st_dev && out.st_ino == named.st_ino ? kStandardOutputName : path;
}

std::string input_path(const std::string& given) {
    if (given != kStandardInputName) return given;
    // Closed (`<&-`), /dev/stdin names no file: say what is missing rather than "no such file".
    if (::fcntl(STDIN_FILENO, F_GETFD) == -1)
        throw UsageError("- reads the scene or preset from standard input, which is closed; redirect a file or a "
                         "program into it (< FILE, PROGRAM |), or name a file");
    return "/dev/stdin";
}

std::string shown_output_name(const std::string& path) {
    return names_standard_output(path) ? "standard output" : path;
}

void refuse_standard_output(const std::string& option, const std::string& path, const std::string& what) {
    if (names_standard_output(path))
        throw UsageError(option + " -: " + what + " cannot go to standard output; name one (./- for one called '-')");
}

}  // namespace brume::app
