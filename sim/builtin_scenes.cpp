#include "sim/builtin_scenes.h"

#include "sim/scene_file.h"

namespace brume {

namespace embedded {
// Defined in the build directory's generated/default_scene_toml.cpp (see sim/CMakeLists.txt).
std::string_view default_scene_toml_text();
}  // namespace embedded

std::string_view default_scene_toml() { return embedded::default_scene_toml_text(); }

Scene default_scene() { return parse_scene_toml(default_scene_toml(), "built-in default scene"); }

}  // namespace brume
