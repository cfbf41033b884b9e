#include "app/cli_util.h"

#include "render/image.h"
#include "render/methods/registry.h"
#include "render/outsized_spheres.h"
#include "render/sun_depth_map.h"
#include "sim/preset.h"
#include "sim/scene_sections.h"
#include "sim/usable_cpus.h"
#include "sim/vdb/volume_loader.h"

#include <vulkan/vulkan.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <limits>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace brume::app {

std::string count_of(std::size_t n, const char* singular, const char* plural) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

void hold_run_to_threads(int threads) {
    if (threads <= 0) return;
    cap_usable_cpus(unsigned(threads));
    ::setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 0);  // 0: a value already set stays
}

void refuse_still_scene(const Preset& preset, const std::string& asked) {
    if (!preset.still) return;
    std::string sections;
    for (const std::string_view s : kPresetSections) {
        const bool many = s == "emitter" || s == "force";  // arrays of tables, as a preset writes them
        sections += std::string(sections.empty() ? "" : ", ") + (many ? "[[" : "[") + std::string(s) + (many ? "]]" : "]");
    }
    throw UsageError(asked + ", and " + preset.scene.source + " is a scene, a still (it has none of a preset's sections: " +
                     sections + "): brume render draws it, and an [[emitter]] or a [camera_path] makes it a preset");
}

bool note_outsized_spheres(const Scene& scene) {
    if (!scene.lighting.shadows || scene.render.shadow_technique != ShadowTechnique::Accurate) return false;
    const std::size_t over = outsized_sphere_count(scene);
    if (over <= std::size_t(kMaxOutsized)) return false;
    if (SunDepthMap::takes_spheres_exactly(scene)) return false;  // no lattice for the rest to blur
    std::printf("note: %zu spheres are over %g times the median radius; accurate shadows take the %d largest whole "
                "and the rest stay in the shadow map, which they may blur past its stated error (docs/accuracy.md, "
                "\"Scenes the map's spacing does not fit\")\n",
                over, kOutsizedRadii, kMaxOutsized);
    return true;
}

void print_volume_report(const VolumeReport& r) {
    std::printf("%s: %s from %llu active voxels, optical-depth error %.2f%% RMS (%.1f%% max) over %ld rays, %.2f s%s\n",
                r.source.c_str(), count_of(r.spheres, "sphere", "spheres").c_str(), static_cast<unsigned long long>(r.active_voxels), 100.0 * r.error.relative_rms,
                100.0 * r.error.relative_max, r.error.rays, r.seconds, r.from_cache ? " (from the conversion cache)" : "");
}

std::uint64_t parse_bytes(const std::string& text) {
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        throw UsageError("'" + text + "' is not a size (examples: 64M, 2G, 1048576)");
    }
    std::string unit = text.substr(used);
    std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    double scale = 0;
    if (unit.empty() || unit == "b") scale = 1;
    else if (unit == "k" || unit == "kb" || unit == "kib") scale = 1024.0;
    else if (unit == "m" || unit == "mb" || unit == "mib") scale = 1024.0 * 1024.0;
    else if (unit == "g" || unit == "gb" || unit == "gib") scale = 1024.0 * 1024.0 * 1024.0;
    else if (unit == "t" || unit == "tb" || unit == "tib") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
    if (scale == 0 || !std::isfinite(value) || value <= 0 || value * scale > 1.8e19)
        throw UsageError("'" + text + "' is not a positive size: a number of bytes with K, M, G or T "
                                    "(powers of 1024), e.g. 64M, 2G, 1T, 1048576");
    return std::uint64_t(value * scale);
}

std::optional<long long> parse_whole_number(std::string_view text) {
    long long value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end || text.empty()) return std::nullopt;  // overflow, junk or nothing
    return value;
}

void check_output_format(const std::string& option, const std::string& path, const std::string& extension) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext.empty() || ext == extension) return;
    // What each extension's writer writes, and the other option that writes what the name says.
    const char* format = extension == ".exr"   ? "linear OpenEXR"
                         : extension == ".png" ? "PNG"
                         : extension == ".vdb" ? "an OpenVDB file"
                                               : "a scene (TOML)";
    const char* other = extension == ".exr" ? " (--png writes PNG)" : extension == ".png" ? " (-o writes OpenEXR)" : "";
    throw UsageError(option + " " + path + ": " + option + " writes " + format + ", but the name ends in " + ext +
                     "; name it " + extension + other);
}

void refuse_non_finite(const Image& image, const std::string& what) {
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < image.rgb.size(); ++i)
        if (!std::isfinite(image.rgb[i]) && bad++ == 0) first = i / 3;
    if (bad == 0) return;
    const std::size_t w = std::size_t(std::max(image.width, 1));
    throw std::runtime_error(what + " has " + std::to_string(bad) + " non-finite (NaN or infinite) values, the first at pixel (" +
                             std::to_string(first % w) + ", " + std::to_string(first / w) +
                             "): the scene's numbers are out of the renderer's range; nothing was written");
}

void check_method_usage(const std::string& method, unsigned given_options) {
    try {
        check_method_spec(method);
        check_method_options(method, given_options);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

void check_device_options(const std::string& method, const std::string& device, bool validate) {
    if (find_method(method).needs_device || (device.empty() && !validate)) return;
    const std::string given = !device.empty() && validate ? "--device and --validate" : !device.empty() ? "--device" : "--validate";
    throw UsageError(given + " applies to the methods that run on a Vulkan device, not to method '" +
                     find_method(method).name + "', which runs on the CPU alone");
}

std::string refuse_empty_path(const std::string& text) {
    return text.empty() ? "an empty file name (leave the option out for the default)" : "";
}

namespace {

// `text` read whole as a number (from_chars: no leading space or '+'), or NaN.
double whole_number_text(const std::string& text) {
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    return ec == std::errc() && ptr == end && !text.empty() ? value : std::numeric_limits<double>::quiet_NaN();
}

std::string got(const std::string& text) { return " (got \"" + text.substr(0, 40) + (text.size() > 40 ? "...\")" : "\")"); }

}  // namespace

std::string refuse_non_positive(const std::string& text) {
    const double value = whole_number_text(text);
    return std::isfinite(value) && value > 0.0 ? "" : "not a positive number" + got(text);
}

std::string refuse_outside_unit_interval(const std::string& text) {
    const double v = whole_number_text(text);
    return v >= 0.0 && v <= 1.0 ? "" : "not a number in [0, 1]" + got(text);
}

std::string refuse_outside_half_open_unit(const std::string& text) {
    const double v = whole_number_text(text);
    return v > 0.0 && v <= 1.0 ? "" : "not a number in (0, 1]" + got(text);
}

std::string refuse_non_frame_number(const std::string& text) {
    const std::optional<long long> v = parse_whole_number(text);
    if (!v || *v < 0 || *v > INT32_MAX)
        return "not a frame number 0, 1, 2, ..." + got(text);
    return "";
}

void parse_size(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find_first_of("xX");
    const std::optional<long long> w = x == std::string::npos ? std::nullopt : parse_whole_number(std::string_view(text).substr(0, x));
    const std::optional<long long> h = x == std::string::npos ? std::nullopt : parse_whole_number(std::string_view(text).substr(x + 1));
    if (!w || !h || *w < 1 || *h < 1 || *w > 16384 || *h > 16384)
        throw UsageError("'" + text + "' is not a size WxH with 1 <= W, H <= 16384");
    width = int(*w);
    height = int(*h);
}

std::vector<int> parse_int_list(const std::string& text) {
    std::vector<int> out;
    // A-B:S, each a whole number (overflow-checked), counted in 64 bits so that no step wraps past B.
    const std::size_t dash = text.find('-'), colon = text.find(':');
    if (dash != std::string::npos && colon != std::string::npos && dash < colon) {
        const std::optional<long long> a = parse_whole_number(std::string_view(text).substr(0, dash));
        const std::optional<long long> b = parse_whole_number(std::string_view(text).substr(dash + 1, colon - dash - 1));
        const std::optional<long long> step = parse_whole_number(std::string_view(text).substr(colon + 1));
        if (!a || !b || !step || *step < 1 || *a > *b || *b > INT32_MAX)
            throw UsageError("'" + text + "' is not a range like 2-16:2 (from A to B >= A in steps of S >= 1, each at most " +
                             std::to_string(INT32_MAX) + ")");
        constexpr long long kMaxItems = 10000;  // a benchmark sweep, not a loop that runs for hours
        if ((*b - *a) / *step + 1 > kMaxItems)
            throw UsageError("'" + text + "' has more than " + std::to_string(kMaxItems) + " values");
        for (long long v = *a; v <= *b; v += *step) out.push_back(int(v));
        return out;
    }
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const std::optional<long long> v = parse_whole_number(item);
        if (!v || *v < INT32_MIN || *v > INT32_MAX)
            throw UsageError("'" + text + "' is not a list like 2,4,8 or 2-16:2");
        out.push_back(int(*v));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        if (comma > start) out.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return out;
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void warm_up(const std::function<void()>& frame, double min_ms, int max_frames) {
    const auto start = std::chrono::steady_clock::now();
    for (int n = 0; n < max_frames; ++n) {
        frame();
        if (std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() >= min_ms) break;
    }
}

double warm_up_ms(int device_type) { return device_type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0.0 : 300.0; }

namespace {

// The length of the well-formed UTF-8 sequence at text[i] (RFC 3629: no overlong forms, no surrogates,
// nothing past U+10FFFF), or 0 when the bytes there are not one.
std::size_t utf8_sequence_length(const std::string& text, std::size_t i) {
    const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
    const unsigned c = byte(i);
    const auto tail = [&](std::size_t k, unsigned lo = 0x80, unsigned hi = 0xBF) { return byte(k) >= lo && byte(k) <= hi; };
    if (c < 0x80) return 1;
    if (c >= 0xC2 && c <= 0xDF) return tail(i + 1) ? 2 : 0;
    if (c == 0xE0) return tail(i + 1, 0xA0) && tail(i + 2) ? 3 : 0;
    if (c == 0xED) return tail(i + 1, 0x80, 0x9F) && tail(i + 2) ? 3 : 0;
    if (c >= 0xE1 && c <= 0xEF) return tail(i + 1) && tail(i + 2) ? 3 : 0;
    if (c == 0xF0) return tail(i + 1, 0x90) && tail(i + 2) && tail(i + 3) ? 4 : 0;
    if (c >= 0xF1 && c <= 0xF3) return tail(i + 1) && tail(i + 2) && tail(i + 3) ? 4 : 0;
    if (c == 0xF4) return tail(i + 1, 0x80, 0x8F) && tail(i + 2) && tail(i + 3) ? 4 : 0;
    return 0;
}

}  // namespace

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const std::size_t n = utf8_sequence_length(text, i);
        if (n == 0) {
            // JSON is Unicode text: a byte that is no UTF-8 (a file name in Latin-1) becomes U+FFFD, as
            // decoders replace it, so that strict parsers read the statistics.
            out += "\\ufffd";
            ++i;
        } else if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
            ++i;
        } else if (c < 0x20) {
            char esc[8];
            std::snprintf(esc, sizeof esc, "\\u%04x", c);
            out += esc;
            ++i;
        } else {
            out.append(text, i, n);
            i += n;
        }
    }
    return out + "\"";
}

}  // namespace brume::app
