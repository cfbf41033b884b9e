// One scene representation, many ways to resolve it (docs/methods.md): every method takes a Scene
// and returns a linear-radiance Image with the same statistics, so one command can chart them. GPU
// methods implement render/frame/gpu_method.h and run through the frame path.
#pragma once

#include "render/image.h"
#include "render/frame/frame_stats.h"
#include "sim/scene.h"

#include <string>

namespace brume {

class GpuMethod;

class Method {
public:
    virtual ~Method() = default;
    // The full name with settings, e.g. "kbuf:8", as `--method` accepts it.
    virtual std::string name() const = 0;
    // True when the method matches the reference to float precision on every scene it accepts.
    virtual bool exact() const = 0;
    // Renders one frame. A method that keeps state between frames (the sorted method's previous
    // order) assumes consecutive calls are consecutive frames of one animation.
    virtual Image render(const Scene& scene, FrameStats* stats) = 0;
    Image render(const Scene& scene) { return render(scene, nullptr); }
    // The method's frame-path interface, null for methods that do not run on the GPU.
    virtual GpuMethod* gpu() { return nullptr; }
};

}  // namespace brume
