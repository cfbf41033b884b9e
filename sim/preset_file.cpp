// The preset document's entry points (sim/preset_file.h): a preset is read as its [preset] header, the
// scene sections as a scene file has them (sim/scene_sections.h), then the sections that make the scene
// move (sim/preset_sections.h). Writing is in sim/preset_writer.cpp.
#include "sim/preset_file.h"

#include "sim/preset_sections.h"
#include "sim/scene_sections.h"
#include "sim/toml_reader.h"

#include <algorithm>

namespace brume {

namespace {

Preset read_preset(const toml_read::Reader& in, const std::string& source_name) {
    check_preset_root_keys(in);
    Preset p;
    read_preset_header(in, p);
    read_scene_sections(in, p.scene);
    read_preset_sections(in, p);
    p.scene.source = source_name;
    if (p.name.empty()) p.name = preset_name_from_file(source_name);
    p.still = std::ranges::none_of(kPresetSections, [&](std::string_view s) { return in.root().contains(s); });
    return p;
}

// Relative grid files are found beside the document, wherever it is run from (a stream's: from the
// working directory).
void set_base_dirs(Preset& p, const std::filesystem::path& path) {
    const std::string dir = toml_text::relative_base(path);
    for (VdbVolume& v : p.scene.volumes) v.source.base_dir = dir;
    for (EmitterDesc& e : p.emitters)
        if (e.shape == EmitterShape::Density) e.density_source.base_dir = dir;
}

}  // namespace

std::string preset_name_from_file(const std::filesystem::path& file) {
    const std::string stem = file.stem().string();
    std::string name;
    for (const char c : stem.substr(std::min(stem.find_first_not_of('.'), stem.size()))) {
        if (name.size() == kMaxPresetName) break;
        name += is_preset_name_character(c) ? c : '_';
    }
    return name.empty() ? "preset" : name;
}

Preset parse_preset_toml(std::string_view text, const std::string& source_name) {
    return read_preset(toml_read::Reader(text, source_name), source_name);
}

Preset load_preset_file(const std::filesystem::path& path) {
    Preset p = parse_preset_toml(toml_text::read_file(path), path.string());
    set_base_dirs(p, path);
    return p;
}

SceneOrPreset load_scene_or_preset_file(const std::filesystem::path& path) {
    const std::string name = path.string();
    const toml_read::Reader in(toml_text::read_file(path), name);
    const bool preset = std::ranges::any_of(kPresetSections, [&](std::string_view s) { return in.root().contains(s); });
    if (!preset) {
        Scene scene = read_scene(in, name);
        const std::string dir = toml_text::relative_base(path);
        for (VdbVolume& v : scene.volumes) v.source.base_dir = dir;
        return {std::move(scene), std::nullopt};
    }
    Preset p = read_preset(in, name);
    set_base_dirs(p, path);
    return {std::nullopt, std::move(p)};
}

}  // namespace brume
