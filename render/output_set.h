// The outputs of one run, committed together or not at all (issue 14 item 12): a render's EXR, PNG
// and statistics, a played frame's EXR and PNG.
//
// Every output is staged first (written in full and flushed to a temporary file beside it, where a
// full disk or a quota shows), and only when all are staged are they renamed into place, one after
// the other. SIGINT, SIGTERM and SIGHUP are held back from the set's construction to its end, so no
// signal cuts a set in two or leaves a temporary file behind; one that arrives is delivered after.
// Renaming within a directory needs no space, so after staging the only failures left are those of
// rename itself; then the renames already done are undone from hard links to the old files
// (docs/decisions.md, "Outputs").
#pragma once

#include "render/atomic_file.h"

#include <signal.h>

#include <filesystem>
#include <string_view>
#include <vector>

namespace brume {

// Holds back SIGINT, SIGTERM and SIGHUP for its lifetime; a pending one is delivered when the
// previous mask comes back.
class SignalsHeld {
public:
    SignalsHeld();
    SignalsHeld(const SignalsHeld&) = delete;
    SignalsHeld& operator=(const SignalsHeld&) = delete;
    ~SignalsHeld();

private:
    sigset_t previous_{};
};

class OutputSet {
public:
    // Throws FileWriteError naming the path; what was staged before is removed by the destructor.
    void stage(const std::filesystem::path& path, std::string_view bytes);
    // Puts every staged output in place. Throws FileWriteError for the first that cannot be.
    void commit();

private:
    SignalsHeld held_;  // first, so it is released last, after the temporaries are removed
    std::vector<StagedFile> staged_;
};

}  // namespace brume
