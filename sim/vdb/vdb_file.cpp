// The only translation unit that includes OpenVDB (about 10 s to compile): keep it that way.
#include "sim/vdb/vdb_file.h"

#include "sim/scene_file.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/Prune.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <new>
#include <sstream>

namespace brume {

namespace {

namespace vdb = openvdb;

// Beyond this a grid's dense copy (4 bytes a voxel) is refused rather than attempted.
constexpr std::uint64_t kMaxDenseVoxels = std::uint64_t(1) << 30;

std::string quote(const std::string& s) { return "\"" + s + "\""; }

// `source` names the file (its path) or the built-in sample the bytes came from.
[[noreturn]] void fail(const std::string& source, const std::string& problem) {
    throw VdbError(source + ": " + problem);
}
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) { fail(path.string(), problem); }

std::string read_bytes(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory, not a VDB file");
    // A device never ends (/dev/zero): refused before any read, rather than read until memory runs out.
    if (std::filesystem::is_character_file(path, ec) || std::filesystem::is_block_file(path, ec))
        fail(path, "is a device, not a VDB file");
    // A pipe or socket has no size to check and may never end: a volume is read from a file.
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
        fail(path, std::filesystem::is_fifo(path, ec) ? "is a pipe (FIFO), not a VDB file: write the volume to a file"
                                                      : "is not a regular file, not a VDB file");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, std::string("cannot open: ") + std::strerror(errno));
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) fail(path, std::string("cannot read: ") + std::strerror(errno));
    return bytes;
}

// OpenVDB reports some corruption it reads past as a warning and carries on with a tree that may be wrong
// (Tree::readTopology: "multi-buffer trees are no longer supported", for a corrupted buffer count); it
// also warns before some errors it then throws ("unsupported VDB file format"). Its header templates
// compiled here write to std::cerr; its library logs through log4cplus, whose console appender writes to
// std::cout. While it parses, both streams are captured, so that a file it only warned about is refused
// with one line naming it, and no stray line reaches the terminal beside Brume's own error. The streams
// are process-wide: Brume reports through stdio (printf, fprintf), never iostreams, so the swap hides
// nothing of its own.
class CapturedOpenVdbOutput {
public:
    CapturedOpenVdbOutput()
        : saved_out_(std::cout.rdbuf(captured_.rdbuf())), saved_err_(std::cerr.rdbuf(captured_.rdbuf())) {}
    ~CapturedOpenVdbOutput() {
        std::cout.rdbuf(saved_out_);
        std::cerr.rdbuf(saved_err_);
    }
    CapturedOpenVdbOutput(const CapturedOpenVdbOutput&) = delete;
    CapturedOpenVdbOutput& operator=(const CapturedOpenVdbOutput&) = delete;

    // The first message OpenVDB wrote, without colour codes or its "WARNING: " / "WARN: " tag; empty
    // when it wrote none.
    std::string first_message() const {
        const std::string raw = captured_.str();
        std::string text;
        for (std::size_t i = 0; i < raw.size(); ++i) {
            if (raw[i] == '\033') {  // a terminal colour sequence, ESC [ ... m
                while (i < raw.size() && raw[i] != 'm') ++i;
                continue;
            }
            if (raw[i] == '\n') {
                if (text.find_first_not_of(" \t") != std::string::npos) break;
                text.clear();
                continue;
            }
            text += raw[i];
        }
        text.erase(0, std::min(text.size(), text.find_first_not_of(" \t")));
        for (const char* tag : {"WARNING: ", "WARN: ", "ERROR: ", "FATAL: "})
            if (text.rfind(tag, 0) == 0) text.erase(0, std::strlen(tag));
        constexpr std::size_t kMaxEchoed = 200;  // OpenVDB's own words, but bounded all the same
        if (text.size() > kMaxEchoed) text = text.substr(0, kMaxEchoed) + "...";
        return text;
    }

private:
    std::ostringstream captured_;
    std::streambuf* saved_out_;
    std::streambuf* saved_err_;
};

// Every grid, fully loaded. The bytes are parsed from memory with stream exceptions on, so a truncated
// file fails at its first short read; OpenVDB's own file reader instead reads on past the end and
// reports garbage (a missing grid, an absurd allocation).
vdb::GridPtrVecPtr parse_grids(const std::string& bytes, const std::string& path) {
    if (bytes.empty()) fail(path, "empty file, not a VDB file");
    // OpenVDB's magic number, 0x56444220 as a little-endian int32: checked here so that a short non-VDB
    // file is named as such rather than as a truncated one.
    if (bytes.compare(0, 4, " BDV") != 0) fail(path, "not a VDB file (no OpenVDB header)");
    vdb::initialize();  // registers the grid types; idempotent
    std::istringstream in(bytes, std::ios::binary);
    in.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
    try {
        vdb::GridPtrVecPtr grids;
        std::string warning;
        {
            const CapturedOpenVdbOutput captured;
            vdb::io::Stream stream(in, /*delayLoad=*/false);
            grids = stream.getGrids();
            warning = captured.first_message();
        }
        if (!warning.empty()) fail(path, "corrupted VDB file (OpenVDB: " + warning + ")");
        return grids;
    } catch (const VdbError&) {
        throw;
    } catch (const std::ios_base::failure&) {
        fail(path, "truncated or corrupted VDB file (its data ends early)");
    } catch (const vdb::IoError& e) {
        if (std::strstr(e.what(), "not a VDB file")) fail(path, "not a VDB file (no OpenVDB header)");
        fail(path, std::string("corrupted VDB file (OpenVDB: ") + e.what() + ")");
    } catch (const std::bad_alloc&) {
        fail(path, "corrupted VDB file (it asks for an absurd amount of memory)");
    } catch (const std::exception& e) {
        fail(path, std::string("corrupted VDB file (OpenVDB: ") + e.what() + ")");
    }
}

}  // namespace

std::string read_vdb_bytes(const std::filesystem::path& path) { return read_bytes(path); }

namespace {

vdb::GridPtrVecPtr read_grids(const std::filesystem::path& path) { return parse_grids(read_bytes(path), path.string()); }

glm::ivec3 to_ivec3(const vdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

vdb::GridBase::Ptr find_grid(const std::string& path, const vdb::GridPtrVec& grids,
                             const std::string& name) {
    for (const auto& g : grids)
        if (g->getName() == name) return g;
    std::string names;
    for (const auto& g : grids) names += (names.empty() ? "" : ", ") + quote(g->getName());
    fail(path, "no grid named " + quote(name) + (grids.empty() ? " (the file has no grids)" : " (grids: " + names + ")"));
}

// Origin and voxel size of a transform that is a uniform scale and a translation; anything else is refused,
// since a DensityGrid's voxels are axis-aligned cubes.
void read_transform(const std::string& path, const std::string& what, const vdb::math::Transform& xf,
                    DensityGrid& out) {
    if (!xf.isLinear()) fail(path, what + " has a non-linear (frustum) transform; Brume reads only uniform-scale linear transforms");
    const vdb::Vec3d o = xf.indexToWorld(vdb::Vec3d(0.0));
    const vdb::Vec3d axes[3] = {xf.indexToWorld(vdb::Vec3d(1, 0, 0)) - o, xf.indexToWorld(vdb::Vec3d(0, 1, 0)) - o,
                                xf.indexToWorld(vdb::Vec3d(0, 0, 1)) - o};
    const double s = axes[0].length();
    bool uniform = std::isfinite(s) && s > 0.0;
    for (int a = 0; a < 3 && uniform; ++a) {
        vdb::Vec3d expected(0.0);
        expected[a] = s;
        uniform = (axes[a] - expected).length() <= 1e-9 * s;
    }
    if (!uniform) {
        std::ostringstream size;
        size << axes[0].length() << " x " << axes[1].length() << " x " << axes[2].length();
        fail(path, what + " has voxels of " + size.str() +
                       " scene units, or rotated or sheared ones; Brume reads only uniform-scale linear transforms "
                       "(a voxel size and a translation)");
    }
    out.origin = {o.x(), o.y(), o.z()};
    out.voxel_size = s;
}

// The range where the grid's spheres can be rendered in floats (kMinVoxelSize in vdb_file.h says why).
void check_range(const std::string& path, const std::string& what, const DensityGrid& g) {
    const glm::dvec3 lo = g.support_min(), hi = g.support_max();
    const double reach = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    if (g.voxel_size >= kMinVoxelSize && reach <= kMaxCoordinate) return;
    std::ostringstream msg;
    msg << what << " has voxels of " << g.voxel_size << " scene units and reaches " << reach
        << " from the origin; Brume reads grids with voxels of at least " << kMinVoxelSize << " lying within "
        << kMaxCoordinate << " of the origin (rescale the grid's transform)";
    fail(path, msg.str());
}

void fill_values(const std::string& path, const std::string& what, const vdb::FloatGrid& grid,
                 DensityGrid& out) {
    const vdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    const vdb::Coord dim = box.dim();
    const std::uint64_t count = std::uint64_t(dim.x()) * std::uint64_t(dim.y()) * std::uint64_t(dim.z());
    if (count > kMaxDenseVoxels)
        fail(path, what + "'s active bounding box holds " + std::to_string(count) + " voxels, more than the " +
                       std::to_string(kMaxDenseVoxels) + " Brume copies");
    out.min = to_ivec3(box.min());
    out.size = to_ivec3(dim);
    // The reach is known from the box alone: a sparse grid far out (two voxels 2e8 apart) is refused
    // before its dense copy is allocated, not after (it once ended in std::bad_alloc).
    check_range(path, what, out);
    out.values.assign(count, 0.0f);
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const float v = *it;
        if (!std::isfinite(v) || v < 0.0f) {
            const vdb::Coord c = it.getCoord();
            std::ostringstream msg;
            msg << what << " has density " << v << " at voxel (" << c.x() << ", " << c.y() << ", " << c.z()
                << "); densities must be finite and non-negative";
            fail(path, msg.str());
        }
        vdb::CoordBBox b;
        it.getBoundingBox(b);  // one voxel, or a whole tile
        for (int k = b.min().z(); k <= b.max().z(); ++k)
            for (int j = b.min().y(); j <= b.max().y(); ++j)
                for (int i = b.min().x(); i <= b.max().x(); ++i)
                    out.values[out.offset(i - out.min.x, j - out.min.y, k - out.min.z)] = v;
    }
}

std::string encode(const vdb::GridPtrVec& grids) {
    std::ostringstream out(std::ios::binary);
    vdb::io::Stream(out).write(grids);
    return out.str();
}

}  // namespace

std::vector<VdbGridInfo> list_vdb_grids(const std::filesystem::path& path) {
    const vdb::GridPtrVecPtr grids = read_grids(path);
    std::vector<VdbGridInfo> infos;
    for (const auto& g : *grids) {
        VdbGridInfo info;
        info.name = g->getName();
        info.value_type = g->valueType();
        info.grid_class = vdb::GridBase::gridClassToMenuName(g->getGridClass());
        info.active_voxels = g->activeVoxelCount();
        if (info.active_voxels > 0) {
            const vdb::CoordBBox box = g->evalActiveVoxelBoundingBox();
            info.bbox_min = to_ivec3(box.min());
            info.bbox_max = to_ivec3(box.max());
        }
        const vdb::Vec3d vs = g->voxelSize();
        info.voxel_size = {vs.x(), vs.y(), vs.z()};
        infos.push_back(std::move(info));
    }
    return infos;
}

DensityGrid read_density_grid(const std::filesystem::path& path, const std::string& grid_name) {
    return std::move(decode_density_grids(read_bytes(path), path.string(), {grid_name}).front());
}

std::vector<DensityGrid> decode_density_grids(const std::string& bytes, const std::string& source,
                                              const std::vector<std::string>& grid_names, const std::string& if_present) {
    const vdb::GridPtrVecPtr grids = parse_grids(bytes, source);
    std::vector<std::string> names = grid_names;
    if (!if_present.empty())
        for (const auto& g : *grids)
            if (g->getName() == if_present && vdb::gridPtrCast<vdb::FloatGrid>(g)) {
                names.push_back(if_present);
                break;
            }
    std::vector<DensityGrid> result;
    for (const std::string& grid_name : names) {
        const vdb::GridBase::Ptr base = find_grid(source, *grids, grid_name);
        const std::string what = "grid " + quote(grid_name);
        const vdb::FloatGrid::Ptr grid = vdb::gridPtrCast<vdb::FloatGrid>(base);
        if (!grid) fail(source, what + " holds " + base->valueType() + " values; Brume reads float density grids");
        if (grid->background() != 0.0f) {
            std::ostringstream msg;
            msg << what << " has background " << grid->background()
                << "; Brume reads grids whose inactive voxels are empty (background 0)";
            fail(source, msg.str());
        }
        DensityGrid out;
        out.name = grid_name;
        out.active_voxels = grid->activeVoxelCount();
        if (out.active_voxels == 0) fail(source, what + " is empty (no active voxels)");
        read_transform(source, what, grid->transform(), out);
        fill_values(source, what, *grid, out);  // checks the range first
        result.push_back(std::move(out));
    }
    return result;
}

namespace {

vdb::FloatGrid::Ptr to_openvdb(const DensityGrid& grid) {
    vdb::FloatGrid::Ptr out = vdb::FloatGrid::create(0.0f);
    vdb::math::Transform::Ptr xf = vdb::math::Transform::createLinearTransform(grid.voxel_size);
    xf->postTranslate(vdb::Vec3d(grid.origin.x, grid.origin.y, grid.origin.z));
    out->setTransform(xf);
    out->setName(grid.name);
    out->setGridClass(vdb::GRID_FOG_VOLUME);
    auto acc = out->getAccessor();
    for (int k = 0; k < grid.size.z; ++k)
        for (int j = 0; j < grid.size.y; ++j)
            for (int i = 0; i < grid.size.x; ++i)
                if (const float v = grid.at(i, j, k); v != 0.0f)
                    acc.setValue(vdb::Coord(grid.min.x + i, grid.min.y + j, grid.min.z + k), v);
    vdb::tools::prune(out->tree());  // uniform blocks become tiles, as tools write them
    return out;
}

}  // namespace

std::string encode_vdb(const DensityGrid& grid) { return encode_vdb(std::vector<DensityGrid>{grid}); }

std::string encode_vdb(const std::vector<DensityGrid>& grids) {
    vdb::initialize();
    vdb::GridPtrVec out;
    for (const DensityGrid& g : grids) out.push_back(to_openvdb(g));
    return encode(out);
}

std::string encode_fog_sphere_vdb(double radius, const glm::dvec3& center, double voxel_size,
                                  const std::string& grid_name) {
    vdb::initialize();
    vdb::FloatGrid::Ptr grid = vdb::tools::createLevelSetSphere<vdb::FloatGrid>(
        float(radius), vdb::Vec3f(float(center.x), float(center.y), float(center.z)), float(voxel_size));
    vdb::tools::sdfToFogVolume(*grid);
    grid->setName(grid_name);
    return encode({grid});
}

std::string encode_refused_vdb_sample(RefusedVdbSample kind) {
    vdb::initialize();
    vdb::math::Transform::Ptr xf = vdb::math::Transform::createLinearTransform(1.0);
    vdb::GridBase::Ptr grid;
    if (kind == RefusedVdbSample::vector_grid) {
        vdb::Vec3SGrid::Ptr g = vdb::Vec3SGrid::create();
        g->tree().setValue(vdb::Coord(0), vdb::Vec3s(1.0f));
        grid = g;
    } else {
        vdb::FloatGrid::Ptr g = vdb::FloatGrid::create(0.0f);
        g->tree().setValue(vdb::Coord(0), 1.0f);
        if (kind == RefusedVdbSample::far_apart) g->tree().setValue(vdb::Coord(200000000, 0, 0), 1.0f);
        grid = g;
        if (kind == RefusedVdbSample::nonuniform_scale) xf->preScale(vdb::Vec3d(1.0, 2.0, 1.0));
        if (kind == RefusedVdbSample::rotated) xf->postRotate(M_PI / 6.0, vdb::math::Z_AXIS);
    }
    grid->setTransform(xf);
    grid->setName("density");
    return encode({grid});
}

}  // namespace brume

namespace brume {

namespace {

// A smooth, deterministic fractal noise in about [-1, 1]: sums of products of sines at rotated, detuned
// frequencies (no lattice, so no grid-aligned artefacts at any resolution).
double cloud_noise(const glm::dvec3& p) {
    double sum = 0.0, amplitude = 0.5, frequency = 2.3;
    for (int octave = 0; octave < 4; ++octave) {
        const double o = 1.7 * octave;
        sum += amplitude * std::sin(frequency * (0.83 * p.x + 0.31 * p.z) + o) *
               std::sin(frequency * (0.91 * p.y - 0.22 * p.x) + 2.1 + o) *
               std::sin(frequency * (0.77 * p.z + 0.40 * p.y) + 0.7 + o);
        amplitude *= 0.55;
        frequency *= 2.07;
    }
    return 2.2 * sum;
}

vdb::FloatGrid::Ptr level_set_sphere(double radius, const glm::dvec3& c, double voxel) {
    return vdb::tools::createLevelSetSphere<vdb::FloatGrid>(float(radius), vdb::Vec3f(float(c.x), float(c.y), float(c.z)),
                                                            float(voxel));
}

// A cumulus-like cloud: the union of five level-set spheres (csgUnion), made a fog volume, its density
// modulated by fractal noise so the inside is lumpy and the edge ragged.
vdb::FloatGrid::Ptr make_cloud(double voxel) {
    const struct { double r; glm::dvec3 c; } blobs[] = {
        {0.55, {0.0, -0.1, 0.0}}, {0.42, {-0.45, -0.25, 0.1}}, {0.40, {0.48, -0.2, -0.05}},
        {0.36, {0.1, 0.3, 0.05}},  {0.30, {-0.2, -0.3, -0.42}},
    };
    vdb::FloatGrid::Ptr grid;
    for (const auto& b : blobs) {
        vdb::FloatGrid::Ptr s = level_set_sphere(b.r, b.c, voxel);
        if (!grid) grid = s;
        else vdb::tools::csgUnion(*grid, *s);
    }
    vdb::tools::sdfToFogVolume(*grid);
    grid->tree().voxelizeActiveTiles();
    for (auto it = grid->beginValueOn(); it; ++it) {
        const vdb::Vec3d w = grid->indexToWorld(it.getCoord());
        const double n = cloud_noise({w.x(), w.y(), w.z()});
        it.setValue(float(std::clamp(double(*it) * (0.75 + 0.6 * n), 0.0, 1.0)));
    }
    vdb::tools::changeBackground(grid->tree(), 0.0f);
    for (auto it = grid->beginValueOn(); it; ++it)
        if (*it == 0.0f) it.setValueOff();
    vdb::tools::prune(grid->tree());
    return grid;
}

// A wavy sheet about three voxels thick: height y = 0.2 sin(3x) cos(2.5z) over |x|, |z| < 0.85, density
// a tent across the sheet, fading out toward the rim. Thin along one axis: the hard case for spheres.
vdb::FloatGrid::Ptr make_sheet(double voxel) {
    vdb::FloatGrid::Ptr grid = vdb::FloatGrid::create(0.0f);
    grid->setTransform(vdb::math::Transform::createLinearTransform(voxel));
    auto acc = grid->getAccessor();
    const int n = int(std::ceil(0.9 / voxel));
    const double half_thickness = 1.5 * voxel;
    for (int k = -n; k <= n; ++k)
        for (int i = -n; i <= n; ++i) {
            const double x = i * voxel, z = k * voxel;
            const double rim = std::max(std::abs(x), std::abs(z));
            if (rim >= 0.85) continue;
            const double fade = std::min(1.0, (0.85 - rim) / 0.15);
            const double h = 0.2 * std::sin(3.0 * x) * std::cos(2.5 * z);
            const int j_lo = int(std::floor((h - half_thickness) / voxel)), j_hi = int(std::ceil((h + half_thickness) / voxel));
            for (int j = j_lo; j <= j_hi; ++j) {
                const double d = 1.0 - std::abs(j * voxel - h) / half_thickness;
                if (d > 0.0) acc.setValue(vdb::Coord(i, j, k), float(d * fade));
            }
        }
    return grid;
}

}  // namespace

std::span<const SampleVolumeInfo> sample_volumes() {
    static const SampleVolumeInfo kSamples[] = {
        {"cloud", "a lumpy cumulus: five level-set spheres united, as fog, modulated by fractal noise"},
        {"fog-sphere", "a level-set sphere of radius 0.9 as a fog volume: 1 inside, a 3-voxel soft edge"},
        {"sheet", "a wavy sheet three voxels thick, fading toward its square rim"},
    };
    return kSamples;
}

bool is_sample_volume(const std::string& name) {
    for (const SampleVolumeInfo& s : sample_volumes())
        if (name == s.name) return true;
    return false;
}

std::string sample_volume_names() {
    std::string names;
    for (const SampleVolumeInfo& s : sample_volumes()) names += (names.empty() ? "" : ", ") + std::string(s.name);
    return names;
}

std::string encode_sample_volume_vdb(const std::string& name, int resolution) {
    if (resolution < kMinSampleResolution || resolution > kMaxSampleResolution)
        throw VdbError("builtin:" + name + ": resolution must be in [" + std::to_string(kMinSampleResolution) + ", " +
                       std::to_string(kMaxSampleResolution) + "] (got " + std::to_string(resolution) + ")");
    vdb::initialize();
    const double voxel = 2.0 / resolution;  // every sample fits [-1, 1]^3
    vdb::FloatGrid::Ptr grid;
    if (name == "cloud") grid = make_cloud(voxel);
    else if (name == "fog-sphere") {
        grid = level_set_sphere(0.9, glm::dvec3(0.0), voxel);
        vdb::tools::sdfToFogVolume(*grid);
    } else if (name == "sheet") grid = make_sheet(voxel);
    else throw VdbError("builtin:" + name + ": no such built-in volume (there are: " + sample_volume_names() + ")");
    grid->setName("density");
    grid->setGridClass(vdb::GRID_FOG_VOLUME);
    return encode({grid});
}

}  // namespace brume
