#include "render/methods/soft.h"

#include <stdexcept>

namespace brume {

std::unique_ptr<Method> make_soft_method(vk::Device& device, const std::string& setting) {
    if (!setting.empty()) throw std::invalid_argument("method 'soft' takes no setting (got ':" + setting + "')");
    return std::make_unique<SoftMethod>(device);
}

}  // namespace brume
