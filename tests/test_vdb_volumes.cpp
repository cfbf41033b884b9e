// [[vdb]] volumes in scenes (sim/vdb/volume_loader.h): converted within their tolerance from the scene's
// camera too, placed by their transform, framed when the scene leaves the camera to them, tinted by an
// albedo grid, and never rendered unconverted.
#include "render/reference.h"
#include "sim/scene_file.h"
#include "sim/volume_transform.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/optical_depth_error.h"
#include "sim/vdb/sphere_cloud.h"
#include "sim/vdb/vdb_file.h"
#include "sim/vdb/volume_loader.h"

#include "tests/vdb_test_samples.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <string>

namespace brume {
namespace {

using namespace vdb_test;

class VdbVolumeFiles : public ScratchDir {};

TEST(VdbVolumes, FourLinesOfTomlFrameAndConvertTheCloud) {
    Scene scene = parse_scene_toml("[[vdb]]\nfile = \"builtin:cloud:32\"\nextinction_scale = 4.0\ntolerance = 0.05\n", "four.toml");
    ASSERT_EQ(scene.volumes.size(), 1u);
    EXPECT_TRUE(scene.frame_volumes);
    const std::vector<VolumeReport> reports = convert_scene_volumes(scene);
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_TRUE(scene.volumes.empty());
    EXPECT_FALSE(scene.frame_volumes);
    EXPECT_EQ(reports[0].spheres, scene.spheres.size());
    EXPECT_LE(reports[0].error.relative_rms, 0.05);
    // Mass: the grid's, times the extinction scale.
    DensitySource source;
    source.file = "builtin:cloud:32";
    const DensityGrid grid = read_density_source(source);
    EXPECT_NEAR(spheres_extinction_mass(scene.spheres), 4.0 * grid.mass(), 1e-9 * grid.mass());
    // Framed: every sphere in front of the camera and inside its vertical field of view.
    const glm::dvec3 forward = glm::normalize(scene.camera.look_at - scene.camera.position);
    for (const Sphere& s : scene.spheres) {
        const glm::dvec3 v = s.center - scene.camera.position;
        ASSERT_GT(glm::dot(v, forward), 0.0);
        ASSERT_LT(std::acos(glm::dot(glm::normalize(v), forward)), scene.camera.fov_y_deg * M_PI / 360.0);
    }
    // The scene camera's own view is within tolerance (it was among the conversion's views).
    EXPECT_LE(measure_optical_depth_error(grid, 4.0, scene.spheres, scene.camera).relative_rms, 0.05 * 1.25);
}

TEST(VdbVolumes, APlacedCameraStaysWhereItWas) {
    Scene scene = parse_scene_toml("[camera]\nposition = [0.0, 0.0, 9.0]\nlook_at = [0.0, 0.0, 0.0]\n"
                                   "[[vdb]]\nfile = \"builtin:fog-sphere:16\"\n",
                                   "placed.toml");
    EXPECT_FALSE(scene.frame_volumes);
    convert_scene_volumes(scene);
    EXPECT_EQ(scene.camera.position, glm::dvec3(0.0, 0.0, 9.0));
    EXPECT_EQ(scene.camera.look_at, glm::dvec3(0.0));
}

TEST(VdbVolumes, TheTransformPlacesEverySphere) {
    const std::string plain = "[camera]\nposition = [0.0, 0.0, 9.0]\n[[vdb]]\nfile = \"builtin:cloud:24\"\ntolerance = 0.1\n";
    Scene reference = parse_scene_toml(plain, "plain.toml");
    convert_scene_volumes(reference);
    // The transform also moves the camera's view of the grid: keep the camera fixed relative to the grid, so
    // the conversion (which measures from it) picks the same cells.
    VolumeTransform t;
    t.translate = {1.0, -2.0, 3.0};
    t.scale = 2.5;
    t.rotate_deg = {10.0, 35.0, -20.0};
    const glm::dvec3 eye = volume_to_world(t, {0.0, 0.0, 9.0}), target = volume_to_world(t, glm::dvec3(0.0));
    const glm::dvec3 up = volume_to_world(t, {0.0, 1.0, 0.0}) - target;
    char text[512];
    std::snprintf(text, sizeof text,
                  "[camera]\nposition = [%.17g, %.17g, %.17g]\nlook_at = [%.17g, %.17g, %.17g]\nup = [%.17g, %.17g, %.17g]\n"
                  "[[vdb]]\nfile = \"builtin:cloud:24\"\ntolerance = 0.1\ntranslate = [1.0, -2.0, 3.0]\nscale = 2.5\n"
                  "rotate = [10.0, 35.0, -20.0]\n",
                  eye.x, eye.y, eye.z, target.x, target.y, target.z, up.x, up.y, up.z);
    Scene placed = parse_scene_toml(text, "placed.toml");
    convert_scene_volumes(placed);
    ASSERT_EQ(placed.spheres.size(), reference.spheres.size());
    for (std::size_t i = 0; i < placed.spheres.size(); ++i) {
        const Sphere& a = reference.spheres[i];
        const Sphere& b = placed.spheres[i];
        ASSERT_NEAR(glm::length(b.center - volume_to_world(t, a.center)), 0.0, 1e-9) << i;
        ASSERT_NEAR(b.radius, 2.5 * a.radius, 1e-12);
        ASSERT_EQ(b.extinction, a.extinction);  // per scene unit: a bigger cloud is optically thicker
    }
}

TEST_F(VdbVolumeFiles, RelativeFilesAreFoundBesideTheSceneAndAlbedoGridsTint) {
    // density 1 everywhere on 8^3 voxels; albedo 0.25 for x < 0, 0.75 for x > 0.
    DensityGrid density = analytic_grid(8, 0.25, [](glm::dvec3) { return 1.0; });
    DensityGrid albedo = analytic_grid(8, 0.25, [](glm::dvec3 p) { return p.x < 0.0 ? 0.25 : 0.75; });
    albedo.name = "tint";
    fs::create_directories(dir_ / "assets");
    write_bytes(dir_ / "assets" / "two.vdb", encode_vdb(std::vector<DensityGrid>{density, albedo}));
    write_bytes(dir_ / "scene.toml", "[[vdb]]\nfile = \"assets/two.vdb\"\nalbedo_grid = \"tint\"\nalbedo = [1.0, 0.8, 0.6]\n"
                                     "tolerance = 0.3\n");
    Scene scene = load_scene_file(dir_ / "scene.toml");
    convert_scene_volumes(scene);
    ASSERT_FALSE(scene.spheres.empty());
    double low = 1.0, high = 0.0;
    for (const Sphere& s : scene.spheres) {
        EXPECT_NEAR(s.albedo.y / s.albedo.x, 0.8, 1e-9);
        EXPECT_NEAR(s.albedo.z / s.albedo.x, 0.6, 1e-9);
        EXPECT_GE(s.albedo.x, 0.25 - 1e-6);
        EXPECT_LE(s.albedo.x, 0.75 + 1e-6);
        low = std::min(low, s.albedo.x), high = std::max(high, s.albedo.x);
    }
    EXPECT_LT(low, 0.4);   // the x < 0 side is darker ...
    EXPECT_GT(high, 0.6);  // ... than the x > 0 side
}

TEST_F(VdbVolumeFiles, AFileWithAnAlbedoGridTintsByDefault) {
    // What vdb-export writes: "density" and "albedo". Unset albedo_grid uses it; "" turns it off.
    DensityGrid density = analytic_grid(8, 0.25, [](glm::dvec3) { return 1.0; });
    DensityGrid albedo = analytic_grid(8, 0.25, [](glm::dvec3) { return 0.5; });
    albedo.name = "albedo";
    write_bytes(dir_ / "exported.vdb", encode_vdb(std::vector<DensityGrid>{density, albedo}));
    write_bytes(dir_ / "plain.vdb", encode_vdb(density));
    const auto albedos = [&](const std::string& text) {
        write_bytes(dir_ / "s.toml", text);
        Scene scene = load_scene_file(dir_ / "s.toml");
        convert_scene_volumes(scene);
        double lo = 1.0, hi = 0.0;
        for (const Sphere& s : scene.spheres) lo = std::min(lo, s.albedo.x), hi = std::max(hi, s.albedo.x);
        return std::make_pair(lo, hi);
    };
    const auto tinted = albedos("[[vdb]]\nfile = \"exported.vdb\"\ntolerance = 0.3\n");
    EXPECT_NEAR(tinted.first, 0.5, 1e-6);
    EXPECT_NEAR(tinted.second, 0.5, 1e-6);
    const auto off = albedos("[[vdb]]\nfile = \"exported.vdb\"\nalbedo_grid = \"\"\ntolerance = 0.3\n");
    EXPECT_EQ(off.first, 1.0);
    EXPECT_EQ(off.second, 1.0);
    const auto plain = albedos("[[vdb]]\nfile = \"plain.vdb\"\ntolerance = 0.3\n");  // no albedo grid: no tint
    EXPECT_EQ(plain.first, 1.0);
    write_bytes(dir_ / "s.toml", "[[vdb]]\nfile = \"plain.vdb\"\nalbedo_grid = \"albedo\"\n");  // named: required
    Scene required = load_scene_file(dir_ / "s.toml");
    EXPECT_THROW(convert_scene_volumes(required), VdbError);
}

TEST(VdbVolumes, ProblemsNameTheVolume) {
    const auto message = [](const std::string& text) {
        Scene scene = parse_scene_toml(text, "bad.toml");
        try {
            convert_scene_volumes(scene);
        } catch (const VdbError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string missing = message("[[vdb]]\nfile = \"builtin:cloud:16\"\n[[vdb]]\nfile = \"/nonexistent/x.vdb\"\n");
    EXPECT_NE(missing.find("vdb[1]"), std::string::npos) << missing;
    EXPECT_NE(missing.find("/nonexistent/x.vdb"), std::string::npos) << missing;
    const std::string grid = message("[[vdb]]\nfile = \"builtin:cloud:16\"\ngrid = \"smoke\"\n");
    EXPECT_NE(grid.find("no grid named \"smoke\""), std::string::npos) << grid;
    const std::string albedo = message("[[vdb]]\nfile = \"builtin:cloud:16\"\nalbedo_grid = \"tint\"\n");
    EXPECT_NE(albedo.find("no grid named \"tint\""), std::string::npos) << albedo;
    const std::string unreachable = message("[[vdb]]\nfile = \"builtin:sheet:24\"\ntolerance = 0.001\n");
    EXPECT_NE(unreachable.find("vdb[0] (builtin:sheet:24)"), std::string::npos) << unreachable;
    EXPECT_NE(unreachable.find("cannot be met"), std::string::npos) << unreachable;
    // Conversion runs long after the file is read, but its messages still point into the file.
    EXPECT_EQ(unreachable.rfind("bad.toml:1: vdb[0] (builtin:sheet:24): ", 0), 0u) << unreachable;
    const std::string second = message("[[vdb]]\nfile = \"builtin:cloud:16\"\n\n[[vdb]]\nfile = \"builtin:sheet:9999\"\n");
    EXPECT_EQ(second.rfind("bad.toml:4: vdb[1]: ", 0), 0u) << second;
    EXPECT_NE(second.find("resolution must be in"), std::string::npos) << second;
    EXPECT_EQ(missing.rfind("bad.toml:3: vdb[1]: ", 0), 0u) << missing;
}

TEST(VdbVolumes, RenderersRefuseUnconvertedVolumes) {
    Scene scene = parse_scene_toml("[[vdb]]\nfile = \"builtin:cloud:16\"\ntolerance = 0.2\n", "unconverted.toml");
    scene.camera.width = scene.camera.height = 8;
    EXPECT_THROW(render_reference(scene, {}), std::logic_error);
    convert_scene_volumes(scene);
    EXPECT_NO_THROW(render_reference(scene, {}));
}

TEST(VdbVolumes, MaxSpheresCapsTheCloud) {
    Scene scene = parse_scene_toml("[[vdb]]\nfile = \"builtin:cloud:32\"\nmax_spheres = 500\n", "capped.toml");
    const std::vector<VolumeReport> reports = convert_scene_volumes(scene);
    EXPECT_LE(scene.spheres.size(), 500u);
    EXPECT_GT(scene.spheres.size(), 100u);
    EXPECT_GT(reports[0].error.relative_rms, 0.0);
}

}  // namespace
}  // namespace brume
