// Camera paths: keyframes pass through their keys and hold at the ends; orbits keep their radius.
#include "sim/camera_path.h"

#include "sim/camera_rays.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace brume {
namespace {

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

Preset keyframed() {
    Preset p;
    p.camera_path.kind = CameraPath::Kind::Keyframes;
    p.camera_path.keys = {{0.0, {0, 1, 10}, {0, 0, 0}}, {1.0, {0, 1, 5}, {0, 0, -1}}, {3.0, {2, 1, 0}, {0, 0, -5}},
                          {4.0, {2, 2, -4}, {0, 0, -9}}};
    return p;
}

TEST(CameraPath, StaticIsTheScenesCamera) {
    Preset p;
    p.scene.camera.position = {1, 2, 3};
    const Camera c = camera_at(p, 7.5);
    expect_near(c.position, {1, 2, 3}, 0.0);
    EXPECT_EQ(c.width, p.scene.camera.width);
}

TEST(CameraPath, KeyframesPassThroughEveryKey) {
    const Preset p = keyframed();
    for (const CameraKey& k : p.camera_path.keys) {
        const Camera c = camera_at(p, k.time);
        expect_near(c.position, k.position, 1e-12);
        expect_near(c.look_at, k.look_at, 1e-12);
    }
}

TEST(CameraPath, KeyframesHoldAtTheEnds) {
    const Preset p = keyframed();
    expect_near(camera_at(p, -2.0).position, p.camera_path.keys.front().position, 0.0);
    expect_near(camera_at(p, 99.0).position, p.camera_path.keys.back().position, 0.0);
}

TEST(CameraPath, KeyframesAreContinuousAcrossKeys) {
    // C1: positions and finite-difference velocities agree on both sides of an interior key.
    const Preset p = keyframed();
    const double t = 1.0, h = 1e-6;
    const glm::dvec3 left = (camera_at(p, t).position - camera_at(p, t - h).position) / h;
    const glm::dvec3 right = (camera_at(p, t + h).position - camera_at(p, t).position) / h;
    expect_near(left, right, 1e-3 * (1.0 + glm::length(left)));
}

TEST(CameraPath, OrbitKeepsRadiusAndHeightAndLooksAtTheCentre) {
    Preset p;
    p.camera_path.kind = CameraPath::Kind::Orbit;
    p.camera_path.orbit_center = {1, 0.5, -2};
    p.camera_path.orbit_radius = 4.0;
    p.camera_path.orbit_height = 1.5;
    p.camera_path.orbit_deg_per_second = 90.0;
    for (double t : {0.0, 0.3, 1.0, 2.7}) {
        const Camera c = camera_at(p, t);
        const glm::dvec3 d = c.position - p.camera_path.orbit_center;
        EXPECT_NEAR(std::hypot(d.x, d.z), 4.0, 1e-12);
        EXPECT_NEAR(d.y, 1.5, 1e-12);
        expect_near(c.look_at, p.camera_path.orbit_center, 0.0);
    }
    // A quarter turn per second: positions one second apart are 90 degrees apart.
    const glm::dvec3 a = camera_at(p, 0.0).position - p.camera_path.orbit_center;
    const glm::dvec3 b = camera_at(p, 1.0).position - p.camera_path.orbit_center;
    EXPECT_NEAR(a.x * b.x + a.z * b.z, 0.0, 1e-9);
}

// Keys that are each valid can join through a view along up: a fly-over straight above what it looks
// at. camera_at refuses that time by name; camera_on_path gives the camera, and make_camera_rays
// refuses it (its rays would be NaN, drawn as background with no error).
TEST(CameraPath, AViewAlongUpBetweenKeysIsRefusedByTime) {
    Preset p;
    p.camera_path.kind = CameraPath::Kind::Keyframes;
    p.camera_path.keys = {{0.0, {-5, 5, 0}, {0, 0, 0}}, {2.0, {5, 5, 0}, {0, 0, 0}}};
    EXPECT_NO_THROW(camera_at(p, 0.9));
    try {
        camera_at(p, 1.0);
        FAIL() << "a view along up was not refused";
    } catch (const CameraPathError& e) {
        EXPECT_NE(std::string(e.what()).find("at 1 s"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("parallel to camera.up"), std::string::npos) << e.what();
    }
    const Camera overhead = camera_on_path(p, 1.0);
    expect_near(overhead.position, {0, 5, 0}, 1e-12);
    EXPECT_THROW(make_camera_rays(overhead), std::invalid_argument);
}

// An orbit about a tilted up faces along it twice a turn; the eye on look_at is refused too.
TEST(CameraPath, AnOrbitFacingAlongATiltedUpIsRefused) {
    Preset p;
    p.scene.camera.up = {0, 0, 1};
    p.camera_path.kind = CameraPath::Kind::Orbit;
    p.camera_path.orbit_radius = 3.0;
    p.camera_path.orbit_height = 0.0;
    p.camera_path.orbit_deg_per_second = 90.0;
    EXPECT_THROW(camera_at(p, 0.0), CameraPathError);  // the eye at +z, looking along -z
    EXPECT_NO_THROW(camera_at(p, 1.0));                // at +x
    Camera c;
    c.look_at = c.position;
    EXPECT_NE(undefined_view(c).find("the eye is on look_at"), std::string::npos);
}

}  // namespace
}  // namespace brume
