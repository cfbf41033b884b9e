#include "app/progress.h"

#include <unistd.h>

#include <cmath>

namespace brume::app {
namespace {

std::string clock_text(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "--:--";
    const long s = long(seconds + 0.5);
    char text[32];
    if (s >= 3600) std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    else std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
    return text;
}

}  // namespace

Progress::Progress(std::string label, int total, std::FILE* out)
    : label_(std::move(label)), total_(total), out_(out), terminal_(::isatty(::fileno(out)) != 0),
      start_(std::chrono::steady_clock::now()) {}

double Progress::elapsed_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::frame_done(int frame_index, const std::string& detail) {
    ++done_;
    const double elapsed = elapsed_seconds();
    const double fps = done_ / std::max(elapsed, 1e-9);
    const double eta = (total_ - done_) / std::max(fps, 1e-9);
    if (terminal_) {
        const int width = 30, filled = total_ > 0 ? done_ * width / total_ : width;
        std::string bar(std::size_t(filled), '=');
        if (filled < width) bar += '>' + std::string(std::size_t(width - filled - 1), ' ');
        std::fprintf(out_, "\r%s [%s] %d/%d  %.2f fps  ETA %s  %s\033[K", label_.c_str(), bar.c_str(), done_,
                     total_, fps, clock_text(eta).c_str(), detail.c_str());
    } else {
        std::fprintf(out_, "%s: frame %04d done (%d/%d, %.2f fps, ETA %s) %s\n", label_.c_str(), frame_index, done_,
                     total_, fps, clock_text(eta).c_str(), detail.c_str());
    }
    std::fflush(out_);
}

void Progress::finish() {
    if (terminal_) std::fprintf(out_, "\n");
    std::fflush(out_);
}

}  // namespace brume::app
