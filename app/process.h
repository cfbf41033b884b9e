// Running an external tool (ffmpeg, gnuplot) without a shell.
#pragma once

#include <string>
#include <vector>

namespace brume::app {

// Runs args[0] (looked up on PATH) with stdout and stderr sent to `log` (or discarded when empty)
// and stdin from /dev/null. Returns its exit status, 128 + signal when killed, -1 when it could not
// start. No shell is involved, so paths need no quoting.
int run_process(const std::vector<std::string>& args, const std::string& log);

}  // namespace brume::app
