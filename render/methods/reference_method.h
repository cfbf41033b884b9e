// The CPU double-precision reference as a Method, timed on the wall clock.
#pragma once

#include "render/methods/method.h"

namespace brume {

class ReferenceMethod : public Method {
public:
    explicit ReferenceMethod(int threads = 0) : threads_(threads) {}
    std::string name() const override { return "reference"; }
    bool exact() const override { return true; }
    Image render(const Scene& scene, FrameStats* stats) override;

private:
    int threads_;
};

}  // namespace brume
