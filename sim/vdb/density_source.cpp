#include "sim/vdb/density_source.h"

#include "sim/vdb/vdb_file.h"

#include <charconv>
#include <string_view>

namespace brume {

namespace {

constexpr std::string_view kBuiltinPrefix = "builtin:";

bool is_builtin(const DensitySource& s) { return std::string_view(s.file).starts_with(kBuiltinPrefix); }

// "cloud" or "cloud:128" after the prefix.
std::string builtin_bytes(const DensitySource& s) {
    const std::string_view rest = std::string_view(s.file).substr(kBuiltinPrefix.size());
    const std::size_t colon = rest.find(':');
    const std::string name(rest.substr(0, colon));
    int resolution = kDefaultSampleResolution;
    if (colon != std::string_view::npos) {
        const std::string_view digits = rest.substr(colon + 1);
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), resolution);
        if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty())
            throw VdbError(s.file + ": the resolution after \"" + name + ":\" must be a whole number of voxels (as in builtin:" +
                           name + ":128)");
    }
    return encode_sample_volume_vdb(name, resolution);
}

}  // namespace

std::string density_source_label(const DensitySource& source) {
    return is_builtin(source) ? source.file : density_source_path(source).string();
}

std::filesystem::path density_source_path(const DensitySource& source) {
    const std::filesystem::path file(source.file);
    if (file.is_absolute() || source.base_dir.empty()) return file;
    return std::filesystem::path(source.base_dir) / file;
}

std::vector<DensityGrid> read_density_source(const DensitySource& source, const std::vector<std::string>& grid_names,
                                             const std::string& if_present) {
    if (source.file.empty()) throw VdbError("a density source needs a file (a .vdb path or builtin:NAME)");
    const std::string bytes = is_builtin(source) ? builtin_bytes(source) : read_vdb_bytes(density_source_path(source));
    return decode_density_grids(bytes, density_source_label(source), grid_names, if_present);
}

DensityGrid read_density_source(const DensitySource& source) {
    return std::move(read_density_source(source, {source.grid}).front());
}

}  // namespace brume
