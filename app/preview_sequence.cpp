#include "app/preview_sequence.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

extern char** environ;

namespace brume::app {

namespace fs = std::filesystem;

SequenceRender::~SequenceRender() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
    }
    std::error_code ignored;
    if (!temporary_.empty()) fs::remove(temporary_, ignored);
    if (!log_.empty()) fs::remove(log_, ignored);
}

void SequenceRender::start(const std::vector<std::string>& play_args, int frames, fs::path temporary) {
    if (pid_ > 0) throw std::runtime_error("a sequence is still rendering");
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error("cannot find this executable to run brume play: " + ec.message());
    static int runs = 0;
    if (!log_.empty()) fs::remove(log_, ec);
    log_ = fs::temp_directory_path() /
           ("brume-preview-sequence-" + std::to_string(::getpid()) + "-" + std::to_string(++runs) + ".log");
    std::vector<std::string> args{self.string(), "play"};
    args.insert(args.end(), play_args.begin(), play_args.end());
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) throw std::runtime_error("cannot start brume play: " + std::string(std::strerror(spawned)));
    if (!temporary_.empty()) fs::remove(temporary_, ec);
    temporary_ = std::move(temporary);
    pid_ = pid;
    done_ = 0;
    total_ = frames;
    status_ = -1;
    last_line_.clear();
}

void SequenceRender::read_log() {
    // Plain progress lines, as play writes them when its output is not a terminal:
    // "NAME: frame 0003 done (2/5, ...". The last of them gives the count.
    std::ifstream in(log_);
    int done = done_;
    for (std::string line; std::getline(in, line);) {
        if (line.empty()) continue;
        // Its error when it had one: play's stderr is unbuffered and its stdout is not, so the header
        // it printed first can land after the error in the log. Else its summary ("wrote N frames in
        // ...") when it got there, else whatever it said last; notes after the summary do not hide it.
        const bool error = line.rfind("brume: error:", 0) == 0, had_error = last_line_.rfind("brume: error:", 0) == 0;
        if (error || (!had_error && (line.rfind("wrote ", 0) == 0 || last_line_.rfind("wrote ", 0) != 0))) last_line_ = line;
        const std::size_t at = line.find(" done (");
        if (at == std::string::npos || line.find(": frame ") == std::string::npos) continue;
        int d = 0, t = 0;
        if (std::sscanf(line.c_str() + at, " done (%d/%d", &d, &t) == 2) done = d;
    }
    done_ = done;
}

void SequenceRender::poll() {
    if (pid_ <= 0) return;
    int status = 0;
    const pid_t ended = ::waitpid(pid_, &status, WNOHANG);
    read_log();
    if (ended == 0) return;
    pid_ = -1;
    status_ = ended < 0 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    std::error_code ignored;
    if (!temporary_.empty()) fs::remove(temporary_, ignored);
    temporary_.clear();
}

}  // namespace brume::app
