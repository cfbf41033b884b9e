// Presets compiled into the binary from presets/*.toml (all but default.toml, the static default
// scene), so `brume play NAME` needs no presets directory at run time.
#pragma once

#include "sim/preset.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brume {

// The built-in names (each file's stem), sorted.
std::vector<std::string> builtin_preset_names();
// The same names as messages list them: "campfire, crossing, ...".
std::string builtin_preset_list();

// The text of presets/NAME.toml as it was when this binary was built; nullopt for an unknown name.
std::optional<std::string_view> builtin_preset_toml(std::string_view name);

// builtin_preset_toml(name) parsed; scene.source is "built-in preset NAME". nullopt for an unknown name.
std::optional<Preset> builtin_preset(std::string_view name);

// The preset `brume play` plays when none is named: "plume".
std::string default_preset_name();

// A path to an existing file, else a built-in name; otherwise a SceneFileError that lists the
// built-in names (and suggests the closest).
Preset resolve_preset(const std::string& name_or_path);

}  // namespace brume
