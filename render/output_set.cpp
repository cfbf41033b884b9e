#include "render/output_set.h"

namespace brume {

SignalsHeld::SignalsHeld() {
    sigset_t hold;
    sigemptyset(&hold);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&hold, s);
    pthread_sigmask(SIG_BLOCK, &hold, &previous_);
}

SignalsHeld::~SignalsHeld() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

void OutputSet::stage(const std::filesystem::path& path, std::string_view bytes) { staged_.emplace_back(path, bytes); }

void OutputSet::commit() {
    for (StagedFile& f : staged_) f.commit();
    staged_.clear();
}

}  // namespace brume
