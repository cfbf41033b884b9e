// The scene sections of a document, [camera] [lighting] [render] [[box]] [[sphere]] [[vdb]], read into
// a validated Scene. parse_scene_toml (sim/scene_file.h) reads these alone; parse_preset_toml reads them
// beside its own sections (sim/preset_sections.h), so the scene format has one reader and does not depend
// on the preset one. Internal to brume_sim, as sim/toml_reader.h is.
#pragma once

#include "sim/scene.h"
#include "sim/toml_reader.h"

#include <array>
#include <string>
#include <string_view>

namespace brume {

// The top-level tables of a scene, in the order messages list them.
inline constexpr std::array<std::string_view, 6> kSceneSections{"camera", "lighting", "render", "box", "sphere", "vdb"};
// The tables only a preset reads (sim/preset_sections.h), named here so that a scene file holding one is
// told to read the file as a preset rather than that the table is unknown.
inline constexpr std::array<std::string_view, 6> kPresetSections{"preset", "timeline",    "emitter",
                                                                 "force",  "camera_path", "render_settings"};
// Where a key misplaced at a scene's top level belongs, one hint per scene section.
extern const std::array<toml_read::SectionHint, 6> kSceneSectionHints;

// Every top-level key of a scene file is a scene section, or the first that is not is reported, pointed to
// where it belongs (a preset section is refused as one).
void check_scene_root_keys(const toml_read::Reader& in);

// Reads the scene sections the document holds into `scene` and sets scene.frame_volumes. The top-level
// keys are the caller's to check: a scene and a preset allow different ones.
void read_scene_sections(const toml_read::Reader& in, Scene& scene);

// A scene file's document: its top-level keys checked, its sections read, `source_name` its source.
Scene read_scene(const toml_read::Reader& in, const std::string& source_name);

// `file` (required: `needs` says who needs it when it is missing) and `grid`: where a [[vdb]] volume or a
// density emitter reads its grid. The file is not opened here: brume_sim does not link OpenVDB, and a
// relative path is taken against the directory of the file that names it, which load_*_file sets afterwards.
void read_density_source(const toml_read::Reader& in, const toml::table& t, const toml_read::KeyPath& path,
                         std::string_view needs, DensitySource& source);

// translate, scale and rotate, each checked by volume_transform_problem on its own so that the message
// points at the key that is wrong; the transform's rules live in one place (sim/volume_transform.h).
VolumeTransform read_volume_transform(const toml_read::Reader& in, const toml::table& t,
                                      const toml_read::KeyPath& path);

}  // namespace brume
