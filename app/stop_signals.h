// SIGINT, SIGTERM, SIGHUP and SIGPIPE (Ctrl-C, kill, a closed terminal or ssh session, a log pipe whose
// reader went away: `brume play ... | head`) set a flag instead of
// ending the process while a StopSignals lives, so that a command finishes what it is writing and
// cleans up as it would on its own: `play` the frame being rendered, `preview` a render-sequence's
// child and its temporary files. The command then exits 130. A signal handler can only reach
// process-wide state, hence the one flag pointer.
#pragma once

#include <atomic>
#include <csignal>

namespace brume::app {

inline std::atomic<bool>* g_stop_signal_flag = nullptr;

extern "C" inline void set_stop_signal_flag(int) {
    if (g_stop_signal_flag) g_stop_signal_flag->store(true);
}

class StopSignals {
public:
    explicit StopSignals(std::atomic<bool>& flag) {
        flag.store(false);
        g_stop_signal_flag = &flag;
        int_ = std::signal(SIGINT, set_stop_signal_flag);
        term_ = std::signal(SIGTERM, set_stop_signal_flag);
        hup_ = std::signal(SIGHUP, set_stop_signal_flag);
        pipe_ = std::signal(SIGPIPE, set_stop_signal_flag);
    }
    ~StopSignals() {
        std::signal(SIGINT, int_);
        std::signal(SIGTERM, term_);
        std::signal(SIGHUP, hup_);
        std::signal(SIGPIPE, pipe_);
        g_stop_signal_flag = nullptr;
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    void (*int_)(int) = SIG_DFL;
    void (*term_)(int) = SIG_DFL;
    void (*hup_)(int) = SIG_DFL;
    void (*pipe_)(int) = SIG_DFL;
};

}  // namespace brume::app
