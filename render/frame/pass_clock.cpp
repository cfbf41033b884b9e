#include "render/frame/pass_clock.h"

#include <stdexcept>

namespace brume {

PassClock::PassClock(const vk::Device& device) : timer_(device, kMaxPasses + 1, "frame.timestamps") {}

void PassClock::start(VkCommandBuffer cmd) {
    names_.clear();
    timer_.reset(cmd);
    timer_.stamp(cmd, 0);
}

void PassClock::mark(VkCommandBuffer cmd, std::string pass) {
    if (names_.size() >= kMaxPasses) throw std::logic_error("more than PassClock::kMaxPasses passes in one frame");
    names_.push_back(std::move(pass));
    timer_.stamp(cmd, std::uint32_t(names_.size()));
}

std::vector<PassTime> PassClock::passes() const {
    std::vector<PassTime> out;
    if (names_.empty()) return out;
    const std::vector<double> ms = timer_.intervals_ms(std::uint32_t(names_.size() + 1));
    for (std::size_t i = 0; i < names_.size(); ++i) out.push_back({names_[i], ms[i]});
    return out;
}

}  // namespace brume
