// The sections a preset adds to a scene, [preset] [timeline] [[emitter]] [[force]] [camera_path]
// [render_settings]: their names and readers. parse_preset_toml (sim/preset_file.h) reads them around the
// scene sections (sim/scene_sections.h), which know nothing of these; preset_to_toml
// (sim/preset_writer.cpp) writes them with the same names. Internal to brume_sim, as sim/toml_reader.h is.
#pragma once

#include "sim/preset.h"
#include "sim/toml_reader.h"

#include <array>
#include <span>
#include <string_view>

namespace brume {

// Names in enum order, as the readers accept them and the writer writes them.
inline constexpr std::array<std::string_view, 5> kShapeNames{"point", "sphere", "box", "disc", "density"};
inline constexpr std::array<std::string_view, 6> kForceNames{"gravity", "buoyancy",   "wind",
                                                             "drag",    "turbulence", "vortex"};
inline constexpr std::array<std::string_view, 3> kCameraPathNames{"static", "keyframes", "orbit"};

// The keys a force of kind k reads beside type, in the order they are written.
std::span<const std::string_view> force_keys(ForceKind k);

// Every top-level key of a preset file is a scene or preset section, or the first that is not is
// reported, pointed to where it belongs.
void check_preset_root_keys(const toml_read::Reader& in);

// [preset], read before the scene sections.
void read_preset_header(const toml_read::Reader& in, Preset& p);

// [timeline] [[emitter]] [[force]] [camera_path] [render_settings], read after the scene sections: the
// timeline's resolution overrides [camera]'s size, and camera keys are checked against its up vector.
void read_preset_sections(const toml_read::Reader& in, Preset& p);

}  // namespace brume
