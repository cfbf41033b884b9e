// Scenes compiled into the binary, so `brume` renders something useful with no files at hand.
#pragma once

#include "sim/scene.h"

#include <string_view>

namespace brume {

// The text of presets/default.toml as it was when this binary was built.
std::string_view default_scene_toml();

// default_scene_toml() parsed; source is "built-in default scene".
Scene default_scene();

}  // namespace brume
