#include "render/output_set.h"

#include <unistd.h>

#include <algorithm>

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
    // Files first, devices last: a device cannot take its bytes back, a file can be put back.
    std::vector<std::size_t> order(staged_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_partition(order.begin(), order.end(), [&](std::size_t i) { return !staged_[i].target().in_place; });
    // Each old file keeps a second name until the whole set is in place, so a failed rename puts
    // back what the earlier renames replaced (and removes what they created).
    std::vector<std::filesystem::path> old(staged_.size());
    for (std::size_t i = 0; i < staged_.size(); ++i)
        if (!staged_[i].target().in_place) old[i] = link_old_file(staged_[i].target().path);
    std::size_t done = 0;
    try {
        for (; done < order.size(); ++done) staged_[order[done]].commit();
    } catch (...) {
        for (std::size_t k = 0; k < done; ++k) {
            const std::size_t i = order[k];
            if (staged_[i].target().in_place) continue;
            if (!old[i].empty()) {
                ::rename(old[i].c_str(), staged_[i].target().path.c_str());
                old[i].clear();
            } else {
                ::unlink(staged_[i].target().path.c_str());
            }
        }
        for (const std::filesystem::path& o : old)
            if (!o.empty()) ::unlink(o.c_str());
        staged_.clear();  // the temporaries not renamed are removed now, not when the set goes
        throw;
    }
    for (const std::filesystem::path& o : old)
        if (!o.empty()) ::unlink(o.c_str());
    staged_.clear();
}

}  // namespace brume
