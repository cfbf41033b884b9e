#include "sim/vdb/conversion_cache.h"

#include "render/atomic_file.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

namespace brume {

namespace {

// 64-bit FNV-1a: simple, fast enough for a 256^3 grid (64 MiB in well under a second), and good enough
// against accidental collisions (the entry also stores its full key, which a load compares).
struct Fnv {
    std::uint64_t h = 0xcbf29ce484222325ull;
    void bytes(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    }
};

std::string hex64(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

// Doubles as hexadecimal floats: exact, so keys differ exactly when the options do.
void add(std::string& key, std::string_view name, double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%a", v);
    key.append(name).append(" ").append(text).append("\n");
}
void add(std::string& key, std::string_view name, long long v) {
    key.append(name).append(" ").append(std::to_string(v)).append("\n");
}
void add(std::string& key, std::string_view name, const glm::dvec3& v) {
    char text[200];
    std::snprintf(text, sizeof text, "%a %a %a", v.x, v.y, v.z);
    key.append(name).append(" ").append(text).append("\n");
}

std::string grid_hash(const DensityGrid& g) {
    Fnv f;
    f.bytes(&g.size, sizeof g.size);
    f.bytes(&g.min, sizeof g.min);
    f.bytes(&g.origin, sizeof g.origin);
    f.bytes(&g.voxel_size, sizeof g.voxel_size);
    f.bytes(&g.active_voxels, sizeof g.active_voxels);  // the fit's default cap depends on it
    f.bytes(g.values.data(), g.values.size() * sizeof(float));
    return hex64(f.h) + " " + std::to_string(g.values.size());
}

// The entry's layout: magic, a byte-order mark (a cache shared by machines of another byte order reads
// as a miss), the key, the cloud, then a checksum of everything before it.
constexpr char kMagic[8] = {'B', 'R', 'M', 'V', 'D', 'B', 'C', '1'};
constexpr std::uint32_t kByteOrder = 0x01020304u;

class Writer {
public:
    template <class T>
    void put(const T& v) {
        out.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    std::string out;
};

class Reader {
public:
    explicit Reader(std::string_view in) : in_(in) {}
    template <class T>
    bool get(T& v) {
        if (in_.size() - pos_ < sizeof v) return false;
        std::memcpy(&v, in_.data() + pos_, sizeof v);
        pos_ += sizeof v;
        return true;
    }
    bool get(std::string& s, std::uint64_t n) {
        if (in_.size() - pos_ < n) return false;
        s.assign(in_.data() + pos_, std::size_t(n));
        pos_ += std::size_t(n);
        return true;
    }
    std::size_t pos() const { return pos_; }

private:
    std::string_view in_;
    std::size_t pos_ = 0;
};

std::filesystem::path entry_path(const std::filesystem::path& dir, const std::string& key) {
    Fnv f;
    f.bytes(key.data(), key.size());
    return dir / (hex64(f.h) + ".spheres");
}

std::string encode(const std::string& key, const SphereCloud& c) {
    Writer w;
    w.out.append(kMagic, sizeof kMagic);
    w.put(kByteOrder);
    w.put(std::uint64_t(key.size()));
    w.out += key;
    w.put(std::uint64_t(c.spheres.size()));
    for (const Sphere& s : c.spheres) {
        w.put(s.center), w.put(s.radius), w.put(s.extinction), w.put(s.albedo), w.put(s.emission);
    }
    const OpticalDepthError& e = c.error;
    w.put(e.relative_rms), w.put(e.relative_max), w.put(e.bias), w.put(e.absolute_rms), w.put(e.transmittance_mean);
    w.put(e.max_grid_depth), w.put(std::int64_t(e.rays));
    w.put(c.split_threshold), w.put(std::int32_t(c.max_cell_voxels)), w.put(c.lattice_spacing);
    w.put(std::int32_t(c.clouds_tried)), w.put(std::uint8_t(c.fitted)), w.put(std::int32_t(c.fit_rounds));
    w.put(std::uint8_t(c.met_tolerance));
    Fnv sum;
    sum.bytes(w.out.data(), w.out.size());
    w.put(sum.h);
    return w.out;
}

std::optional<SphereCloud> decode(std::string_view bytes, const std::string& key) {
    if (bytes.size() < sizeof kMagic + sizeof(std::uint64_t) || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        return std::nullopt;
    // The checksum first: nothing of a damaged entry is trusted, not even its lengths.
    std::uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
    Fnv sum;
    sum.bytes(bytes.data(), bytes.size() - sizeof stored);
    if (sum.h != stored) return std::nullopt;
    Reader r(bytes.substr(sizeof kMagic, bytes.size() - sizeof kMagic - sizeof stored));
    std::uint32_t order = 0;
    std::uint64_t key_size = 0, count = 0;
    std::string entry_key;
    if (!r.get(order) || order != kByteOrder || !r.get(key_size) || !r.get(entry_key, key_size) || entry_key != key ||
        !r.get(count))
        return std::nullopt;
    // Each sphere takes 11 doubles: a count the bytes cannot hold is damage, not an allocation to try.
    if (count > bytes.size() / (11 * sizeof(double))) return std::nullopt;
    SphereCloud c;
    c.spheres.resize(std::size_t(count));
    for (Sphere& s : c.spheres)
        if (!r.get(s.center) || !r.get(s.radius) || !r.get(s.extinction) || !r.get(s.albedo) || !r.get(s.emission))
            return std::nullopt;
    OpticalDepthError& e = c.error;
    std::int64_t rays = 0;
    std::int32_t max_cell = 0, tried = 0, rounds = 0;
    std::uint8_t fitted = 0, met = 0;
    if (!r.get(e.relative_rms) || !r.get(e.relative_max) || !r.get(e.bias) || !r.get(e.absolute_rms) ||
        !r.get(e.transmittance_mean) || !r.get(e.max_grid_depth) || !r.get(rays) || !r.get(c.split_threshold) ||
        !r.get(max_cell) || !r.get(c.lattice_spacing) || !r.get(tried) || !r.get(fitted) || !r.get(rounds) || !r.get(met))
        return std::nullopt;
    if (r.pos() != bytes.size() - sizeof kMagic - sizeof stored) return std::nullopt;  // trailing bytes
    e.rays = long(rays);
    c.max_cell_voxels = max_cell;
    c.clouds_tried = tried;
    c.fitted = fitted != 0;
    c.fit_rounds = rounds;
    c.met_tolerance = met != 0;
    return c;
}

// BRUME_CACHE: unset or a word for on, a word for off; any other value is refused by name, so that a
// typo ("of") does not leave the cache on unnoticed.
bool switched_off(const char* v) {
    if (!v) return false;
    std::string s(v);
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (s == "off" || s == "0" || s == "no" || s == "false") return true;
    if (s == "on" || s == "1" || s == "yes" || s == "true") return false;
    throw std::invalid_argument("BRUME_CACHE='" + std::string(v).substr(0, 80) +
                                "': 'off' (or 0, no, false) or 'on' (or 1, yes, true)");
}

}  // namespace

std::filesystem::path conversion_cache_dir() {
    if (switched_off(std::getenv("BRUME_CACHE"))) return {};
    if (const char* d = std::getenv("BRUME_CACHE_DIR"); d && *d) return std::filesystem::path(d);
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x && std::filesystem::path(x).is_absolute())
        return std::filesystem::path(x) / "brume" / "vdb";
    // A HOME that does not exist (a service account's /nonexistent) is not made: no cache, as without one.
    std::error_code ec;
    if (const char* h = std::getenv("HOME"); h && *h && std::filesystem::is_directory(h, ec))
        return std::filesystem::path(h) / ".cache" / "brume" / "vdb";
    return {};
}

std::string conversion_key(const DensityGrid& grid, const SphereCloudOptions& o, const SphereFitSettings& fit) {
    std::string key;
    add(key, "converter", (long long)kConversionVersion);
    key += "grid " + grid_hash(grid) + "\n";
    if (o.albedo_grid) key += "albedo_grid " + grid_hash(*o.albedo_grid) + "\n";
    add(key, "tolerance", o.tolerance);
    add(key, "max_spheres", (long long)o.max_spheres);
    add(key, "extinction_scale", o.extinction_scale);
    add(key, "albedo", o.albedo);
    add(key, "sphere_scale", o.sphere_scale);
    add(key, "max_cell_voxels", (long long)o.max_cell_voxels);
    add(key, "axis_view_resolution", (long long)o.axis_view_resolution);
    // The measured views are part of the input: the error, and so the spheres chosen, depend on them.
    for (const Camera& c : o.views) {
        add(key, "view", c.position);
        add(key, " look_at", c.look_at);
        add(key, " up", c.up);
        add(key, " fov", c.fov_y_deg);
        add(key, " size", (long long)c.width * 100000 + c.height);
    }
    add(key, "fit", (long long)o.fit);
    if (o.fit) {
        add(key, "fit_seed", (long long)fit.seed_spheres);
        add(key, "fit_iterations", (long long)fit.iterations);
        add(key, "fit_growth", fit.growth);
        add(key, "fit_view_resolution", (long long)fit.view_resolution);
        add(key, "fit_merge", (long long)fit.merge);
    }
    return key;
}

std::optional<SphereCloud> load_cached_conversion(const std::filesystem::path& dir, const std::string& key) {
    try {
        std::ifstream in(entry_path(dir, key), std::ios::binary);
        if (!in) return std::nullopt;
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) return std::nullopt;
        return decode(bytes, key);
    } catch (const std::exception&) {  // out of memory for a huge file, a filesystem error
        return std::nullopt;
    }
}

bool store_cached_conversion(const std::filesystem::path& dir, const std::string& key, const SphereCloud& cloud) {
    try {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) return false;
        write_file_atomically(entry_path(dir, key), encode(key, cloud));
        return true;
    } catch (const std::exception&) {  // FileWriteError (read-only, full disk), bad_alloc
        return false;
    }
}

SphereCloud cached_conversion(const DensityGrid& grid, const SphereCloudOptions& options,
                              const std::function<SphereCloud()>& convert, CacheOutcome* outcome) {
    const std::filesystem::path dir = conversion_cache_dir();
    CacheOutcome result = CacheOutcome::Off;
    SphereCloud cloud;
    if (dir.empty()) {
        cloud = convert();
    } else {
        const std::string key = conversion_key(grid, options);
        if (std::optional<SphereCloud> hit = load_cached_conversion(dir, key)) {
            cloud = std::move(*hit);
            result = CacheOutcome::Hit;
        } else {
            cloud = convert();
            result = store_cached_conversion(dir, key, cloud) ? CacheOutcome::Stored : CacheOutcome::NotStored;
        }
    }
    if (outcome) *outcome = result;
    return cloud;
}

}  // namespace brume
