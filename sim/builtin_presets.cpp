#include "sim/builtin_presets.h"

#include "sim/preset_file.h"

#include <filesystem>
#include <span>
#include <utility>

namespace brume {

namespace embedded {
// (name, text) sorted by name; defined in the build directory's generated/builtin_presets_toml.cpp
// (see sim/CMakeLists.txt).
std::span<const std::pair<std::string_view, std::string_view>> builtin_preset_texts();
}  // namespace embedded

std::vector<std::string> builtin_preset_names() {
    std::vector<std::string> names;
    for (const auto& [name, text] : embedded::builtin_preset_texts()) names.emplace_back(name);
    return names;
}

std::optional<std::string_view> builtin_preset_toml(std::string_view name) {
    for (const auto& [n, text] : embedded::builtin_preset_texts())
        if (n == name) return text;
    return std::nullopt;
}

std::optional<Preset> builtin_preset(std::string_view name) {
    const std::optional<std::string_view> text = builtin_preset_toml(name);
    if (!text) return std::nullopt;
    // Messages name the file it was built from; the name is the file's stem unless [preset] says otherwise.
    Preset p = parse_preset_toml(*text, "presets/" + std::string(name) + ".toml");
    p.scene.source = "built-in preset " + std::string(name);
    return p;
}

std::string default_preset_name() { return "plume"; }

std::string builtin_preset_list() {
    std::string list;
    for (const std::string& name : builtin_preset_names()) list += (list.empty() ? "" : ", ") + name;
    return list;
}

Preset resolve_preset(const std::string& name_or_path) {
    // A directory is never a preset: `brume play plume` writes its frames to ./plume/, and playing
    // plume again must still find the built-in.
    std::error_code ec;
    if (std::filesystem::exists(name_or_path, ec) && !std::filesystem::is_directory(name_or_path, ec))
        return load_preset_file(name_or_path);
    if (std::optional<Preset> p = builtin_preset(name_or_path)) return std::move(*p);
    std::vector<std::string_view> names;
    for (const auto& [name, text] : embedded::builtin_preset_texts()) names.push_back(name);
    std::string problem = "no such file, and not a built-in preset";
    if (const auto close = toml_text::suggest(name_or_path, names))
        problem += " (did you mean \"" + std::string(*close) + "\"?)";
    problem += "; built-in presets: " + builtin_preset_list();
    throw SceneFileError(name_or_path, 0, 0, "", problem);
}

}  // namespace brume
