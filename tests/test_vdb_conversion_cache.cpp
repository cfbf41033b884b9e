// The conversion cache (sim/vdb/conversion_cache.h) and fit = true in [[vdb]] tables: a hit gives the
// spheres bit for bit, any changed input or option misses, a damaged entry is recomputed, and a cache that
// cannot be written or is switched off never stops a conversion. Every test points XDG_CACHE_HOME at its
// own scratch directory, so none writes into the real cache.
#include "sim/scene_file.h"
#include "sim/vdb/conversion_cache.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/volume_loader.h"

#include "tests/vdb_test_samples.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace brume {
namespace {

using namespace vdb_test;

constexpr const char* kScene = "[camera]\nposition = [0.0, 0.5, 6.0]\nlook_at = [0.0, 0.0, 0.0]\n"
                               "[[vdb]]\nfile = \"builtin:cloud:24\"\nextinction_scale = 3.0\ntolerance = 0.1\n";

class ConversionCache : public ScratchDir {
protected:
    void SetUp() override {
        ScratchDir::SetUp();
        ::unsetenv("BRUME_CACHE");
        ::unsetenv("BRUME_CACHE_DIR");
        ::setenv("XDG_CACHE_HOME", (dir_ / "xdg").c_str(), 1);
    }
    void TearDown() override {
        ::unsetenv("XDG_CACHE_HOME");
        ::unsetenv("BRUME_CACHE");
        ScratchDir::TearDown();
    }
    fs::path entries() const { return dir_ / "xdg" / "brume" / "vdb"; }
    std::vector<fs::path> entry_files() const {
        std::vector<fs::path> out;
        if (fs::exists(entries()))
            for (const auto& e : fs::directory_iterator(entries()))
                if (e.path().extension() == ".spheres") out.push_back(e.path());
        return out;
    }
    // Converts `text` as a render would, returning the scene's spheres and whether they came from the cache.
    static std::vector<Sphere> convert(const std::string& text, bool* from_cache = nullptr) {
        Scene scene = parse_scene_toml(text, "cached.toml");
        const std::vector<VolumeReport> reports = convert_scene_volumes(scene);
        if (from_cache) *from_cache = reports.at(0).from_cache;
        return scene.spheres;
    }
};

void expect_bit_identical(const std::vector<Sphere>& a, const std::vector<Sphere>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(std::memcmp(&a[i].center, &b[i].center, sizeof a[i].center), 0) << "sphere " << i;
        ASSERT_EQ(std::memcmp(&a[i].radius, &b[i].radius, sizeof(double)), 0) << "sphere " << i;
        ASSERT_EQ(std::memcmp(&a[i].extinction, &b[i].extinction, sizeof(double)), 0) << "sphere " << i;
        ASSERT_EQ(std::memcmp(&a[i].albedo, &b[i].albedo, sizeof a[i].albedo), 0) << "sphere " << i;
    }
}

TEST_F(ConversionCache, AHitGivesTheSameSpheresBitForBit) {
    bool cached = true;
    const std::vector<Sphere> first = convert(kScene, &cached);
    EXPECT_FALSE(cached);
    ASSERT_EQ(entry_files().size(), 1u);  // under $XDG_CACHE_HOME/brume
    const std::vector<Sphere> second = convert(kScene, &cached);
    EXPECT_TRUE(cached);
    expect_bit_identical(first, second);
    // And the cached spheres are what converting without the cache gives.
    ::setenv("BRUME_CACHE", "off", 1);
    expect_bit_identical(first, convert(kScene, &cached));
    EXPECT_FALSE(cached);
}

TEST_F(ConversionCache, AChangedGridOrOptionMisses) {
    DensitySource source;
    source.file = "builtin:cloud:24";
    const DensityGrid grid = read_density_source(source);
    SphereCloudOptions o;
    o.tolerance = 0.1;
    const std::string key = conversion_key(grid, o);
    EXPECT_EQ(key, conversion_key(grid, o));  // the same inputs, the same key
    o.threads = 1;
    EXPECT_EQ(key, conversion_key(grid, o)) << "the thread count does not change the spheres";

    const auto differs = [&](auto&& change) {
        SphereCloudOptions changed = o;
        DensityGrid g = grid;
        change(changed, g);
        return conversion_key(g, changed) != key;
    };
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.tolerance = 0.1000001; }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.max_spheres = 100; }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.extinction_scale = 2.0; }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.albedo = glm::dvec3(0.9); }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.sphere_scale = 1.5; }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.fit = true; }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid&) { c.views.push_back(Camera{}); }));
    EXPECT_TRUE(differs([](SphereCloudOptions& c, DensityGrid& g) { c.albedo_grid = &g; }));
    // One voxel's value, or where the voxels sit, is a different input.
    EXPECT_TRUE(differs([](SphereCloudOptions&, DensityGrid& g) { g.values[g.values.size() / 2] += 1e-3f; }));
    EXPECT_TRUE(differs([](SphereCloudOptions&, DensityGrid& g) { g.voxel_size *= 1.01; }));
    EXPECT_TRUE(differs([](SphereCloudOptions&, DensityGrid& g) { g.origin.x += 0.5; }));

    // Through a scene: another tolerance and another grid each convert anew, beside the first entry.
    bool cached = true;
    convert(kScene, &cached);
    EXPECT_FALSE(cached);
    std::string other = kScene;
    other.replace(other.find("tolerance = 0.1"), 15, "tolerance = 0.15");
    convert(other, &cached);
    EXPECT_FALSE(cached);
    std::string other_grid = kScene;
    other_grid.replace(other_grid.find("cloud:24"), 8, "cloud:20");
    convert(other_grid, &cached);
    EXPECT_FALSE(cached);
    EXPECT_EQ(entry_files().size(), 3u);
    convert(other, &cached);
    EXPECT_TRUE(cached);
}

TEST_F(ConversionCache, ADamagedEntryIsRecomputedAndReplaced) {
    const std::vector<Sphere> reference = convert(kScene);
    ASSERT_EQ(entry_files().size(), 1u);
    const fs::path entry = entry_files()[0];
    const auto size = fs::file_size(entry);
    bool cached = true;

    // Truncated (a job killed mid-copy, a full disk on another writer).
    fs::resize_file(entry, size / 2);
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(cached);
    EXPECT_EQ(fs::file_size(entry), size) << "the recomputed entry replaces the damaged one";

    // One flipped byte near the end (what the conversion measured): the checksum catches it.
    {
        std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(size - 64));
        char c = 0;
        f.read(&c, 1);
        c = char(c ^ 0x10);
        f.seekp(std::streamoff(size - 64));
        f.write(&c, 1);
    }
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(cached);
    convert(kScene, &cached);
    EXPECT_TRUE(cached);

    // Garbage of the right name.
    std::ofstream(entry, std::ios::binary | std::ios::trunc) << "not an entry";
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(cached);
}

TEST_F(ConversionCache, AnUnwritableOrSwitchedOffCacheStillConverts) {
    const std::vector<Sphere> reference = convert(kScene);
    // A cache directory that cannot be created (a regular file stands where a directory must be; the tests
    // may run as root, so permissions alone would not stop the write).
    std::ofstream(dir_ / "file") << "x";
    ::setenv("XDG_CACHE_HOME", (dir_ / "file" / "below").c_str(), 1);
    bool cached = true;
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(cached);
    SphereCloud cloud;
    cloud.spheres = reference;
    EXPECT_FALSE(store_cached_conversion(dir_ / "file" / "below", "key", cloud));

    // Relative XDG_CACHE_HOME is ignored (the XDG specification): $HOME/.cache is used instead, when HOME
    // is a directory; a HOME that does not exist (a service account's /nonexistent) is not made: no cache.
    ::setenv("XDG_CACHE_HOME", "relative/dir", 1);
    const std::string saved_home = std::getenv("HOME") ? std::getenv("HOME") : "";
    ::setenv("HOME", dir_.c_str(), 1);
    EXPECT_EQ(conversion_cache_dir(), dir_ / ".cache" / "brume" / "vdb");
    ::setenv("HOME", (dir_ / "nonexistent").c_str(), 1);
    EXPECT_TRUE(conversion_cache_dir().empty());
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(fs::exists(dir_ / "nonexistent"));
    if (saved_home.empty()) ::unsetenv("HOME");
    else ::setenv("HOME", saved_home.c_str(), 1);

    // A value of BRUME_CACHE that is neither on nor off is refused by name, not taken as on.
    ::setenv("BRUME_CACHE", "of", 1);
    EXPECT_THROW(conversion_cache_dir(), std::invalid_argument);
    ::setenv("BRUME_CACHE", "On", 1);
    EXPECT_FALSE(conversion_cache_dir().empty());

    // Off: nothing read, nothing written.
    ::setenv("XDG_CACHE_HOME", (dir_ / "xdg2").c_str(), 1);
    ::setenv("BRUME_CACHE", "off", 1);
    EXPECT_TRUE(conversion_cache_dir().empty());
    expect_bit_identical(reference, convert(kScene, &cached));
    EXPECT_FALSE(cached);
    EXPECT_FALSE(fs::exists(dir_ / "xdg2"));
}

TEST_F(ConversionCache, FitTrueInAVdbTableFitsTheSpheresAndIsCachedToo) {
    const std::string tiled = "[[vdb]]\nfile = \"builtin:fog-sphere:24\"\ntolerance = 0.05\n";
    const std::string fitted = "[[vdb]]\nfile = \"builtin:fog-sphere:24\"\ntolerance = 0.05\nfit = true\n";
    Scene scene = parse_scene_toml(fitted, "fit.toml");
    ASSERT_EQ(scene.volumes.size(), 1u);
    EXPECT_TRUE(scene.volumes[0].fit);
    // The writer keeps it (and a fit may give a cap beside its tolerance; a tiling may not).
    Scene again = parse_scene_toml(scene_to_toml(scene), "again.toml");
    ASSERT_EQ(again.volumes.size(), 1u);
    EXPECT_TRUE(again.volumes[0].fit);
    EXPECT_NO_THROW(parse_scene_toml(fitted + "max_spheres = 50\n", "capped.toml"));
    EXPECT_THROW(parse_scene_toml(tiled + "max_spheres = 50\n", "both.toml"), std::exception);

    bool cached = true;
    const std::vector<Sphere> fit = convert(fitted, &cached);
    EXPECT_FALSE(cached);
    const std::vector<Sphere> tiles = convert(tiled);
    // A fog sphere is one sphere's worth of shape: fitting takes a handful where tiling takes hundreds.
    EXPECT_LE(fit.size(), 8u);
    EXPECT_GT(tiles.size(), 10 * fit.size());
    expect_bit_identical(fit, convert(fitted, &cached));
    EXPECT_TRUE(cached);
}

}  // namespace
}  // namespace brume
