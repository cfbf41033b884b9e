// The CPU double-precision reference as a Method, timed on the wall clock. A scene whose shadow
// technique is per-sphere is rendered in the reference's per-sphere mode, else by the exact model.
#pragma once

#include "render/methods/method.h"

#include <atomic>
#include <cstdint>

namespace brume {

class ReferenceMethod : public Method {
public:
    explicit ReferenceMethod(int threads = 0) : threads_(threads) {}
    std::string name() const override { return "reference"; }
    bool exact() const override { return true; }
    Image render(const Scene& scene, FrameStats* stats) override;
    // Each frame's finished pixels are added to `counter` (ReferenceOptions::pixels_done); null: none.
    void count_pixels_into(std::atomic<std::uint64_t>* counter) { pixels_done_ = counter; }

private:
    int threads_;
    std::atomic<std::uint64_t>* pixels_done_ = nullptr;
};

}  // namespace brume
