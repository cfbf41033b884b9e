// One scene representation, many ways to resolve it (GUIDE section 3): every method takes a Scene
// and returns a linear-radiance Image with the same statistics, so one command can chart them.
#pragma once

#include "render/image.h"
#include "render/methods/frame_stats.h"
#include "sim/scene.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brume {

namespace vk {
class Device;
}

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
};

struct MethodInfo {
    std::string name;        // "kbuf"
    std::string setting;     // what the part after ':' means, empty if none
    std::string default_setting;
    std::string summary;     // one line
};

// Every method `make_method` knows, in charting order.
const std::vector<MethodInfo>& method_catalogue();

// "ppll", "reference", "kbuf:8", ... Throws std::invalid_argument naming the method or setting
// and listing the known ones. `device` may be null only for methods that need no GPU.
std::unique_ptr<Method> make_method(vk::Device* device, const std::string& spec);

}  // namespace brume
