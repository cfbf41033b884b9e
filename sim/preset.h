// An animated preset: a static scene (camera, lighting, boxes, fixed spheres) plus what makes it
// move: a timeline, emitters, forces, a camera path and render settings. Plain data; the
// simulator (sim/simulator.h) gives it behaviour and sim/preset_file.h reads and writes it.
#pragma once

#include "sim/scene.h"

#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace brume {

class DensitySampler;  // sim/density_sampler.h

// A value drawn uniformly from [min, max] per particle (min == max: a constant).
struct Range {
    double min = 0.0;
    double max = 0.0;
};

// A colour drawn per channel uniformly from [min, max].
struct ColorRange {
    glm::dvec3 min{1.0};
    glm::dvec3 max{1.0};
};

// How a particle's properties change with its normalised age a = age / lifetime in [0, 1].
struct AgeCurves {
    double radius_growth = 1.0;  // radius(a) = radius0 * (1 + (radius_growth - 1) * a)
    double fade_in = 0.0;        // extinction ramps from 0 to full over a in [0, fade_in]
    double fade_out = 0.0;       // and from full to 0 over a in [1 - fade_out, 1]
    // Albedo multiplier keys (a, rgb), a ascending, linearly interpolated, held at the ends.
    // Empty: a constant multiplier of 1.
    struct AlbedoKey {
        double age = 0.0;
        glm::dvec3 multiplier{1.0};
    };
    std::vector<AlbedoKey> albedo_ramp;
    // Emission multiplier keys on EmitterDesc::emission, the same way (fire: a white-yellow core through
    // orange to soot). Empty: a constant multiplier of 1.
    std::vector<AlbedoKey> emission_ramp;
};

// Density: births spread in proportion to a density grid's trilinear field (a [[vdb]] grid seeding smoke).
enum class EmitterShape { Point, Sphere, Box, Disc, Density };

struct EmitterDesc {
    std::string name;
    // "FILE:LINE" of its [[emitter]] table, which a density emitter's grid errors start with (the grid is
    // read after the file, as a [[vdb]] volume's); "FILE" or empty as VdbVolume::defined_at.
    std::string defined_at;
    EmitterShape shape = EmitterShape::Point;
    glm::dvec3 center{0.0};
    double radius = 0.0;             // Sphere (volume) and Disc
    glm::dvec3 half_extent{0.0};     // Box
    glm::dvec3 normal{0.0, 1.0, 0.0};  // Disc plane normal
    DensitySource density_source;      // Density: the grid, placed in the scene by density_transform
    VolumeTransform density_transform;
    // Density: the grid and its sampling tables, read from density_source before simulating (sim/vdb/ loads
    // it, since brume_sim does not link OpenVDB). Shared, so copying a preset does not copy voxels.
    std::shared_ptr<const DensitySampler> density;
    double rate = 0.0;               // particles per second, emitted continuously
    struct Burst {
        double time = 0.0;           // seconds
        std::uint32_t count = 0;
    };
    std::vector<Burst> bursts;
    double start = 0.0;              // continuous emission window, seconds
    double stop = std::numeric_limits<double>::infinity();
    glm::dvec3 direction{0.0, 1.0, 0.0};  // initial velocity direction (need not be unit)
    Range speed{1.0, 1.0};
    double cone_deg = 0.0;           // half-angle of the cone around `direction`, uniform on the cap
    double jitter = 0.0;             // plus a velocity uniform in a ball of this radius
    Range lifetime{2.0, 2.0};        // seconds
    Range radius_range{0.1, 0.1};
    Range extinction{1.0, 1.0};
    ColorRange albedo;
    glm::dvec3 emission{0.0};  // every particle's emission (scene.h Sphere::emission), times emission_ramp
    AgeCurves curves;
};

enum class ForceKind {
    Gravity,     // a = vector
    Buoyancy,    // a = strength * up (0, 1, 0)
    Wind,        // a = strength * (vector - v): drag toward the wind velocity `vector`
    Drag,        // a = -strength * v (linear drag, 1/s)
    Turbulence,  // a = strength * curl noise(x * scale, t * speed), octaves / lacunarity / gain
    Vortex,      // a = strength * (axis x r) / (|r|^2 + radius^2) about the line (center, axis)
};

struct ForceDesc {
    ForceKind kind = ForceKind::Gravity;
    glm::dvec3 vector{0.0};
    double strength = 0.0;
    double scale = 1.0;
    double speed = 0.0;
    int octaves = 1;
    double lacunarity = 2.0;
    double gain = 0.5;
    glm::dvec3 center{0.0};
    glm::dvec3 axis{0.0, 1.0, 0.0};
    double radius = 1.0;
};

struct Timeline {
    double fps = 24.0;
    double duration = 5.0;               // seconds; frames = round(duration * fps)
    int substeps = 2;                    // simulation steps per frame
    double preroll = 0.0;                // seconds simulated before frame 0
    std::uint64_t seed = 1;
    std::uint32_t max_particles = 100000;  // the particle budget: emission stops while it is full
    int frame_count() const { return int(std::lround(duration * fps)); }
};

struct CameraKey {
    double time = 0.0;
    glm::dvec3 position{0.0};
    glm::dvec3 look_at{0.0};
};

struct CameraPath {
    enum class Kind { Static, Keyframes, Orbit };
    Kind kind = Kind::Static;        // Static: the scene's [camera] for every frame
    std::vector<CameraKey> keys;     // Keyframes: time ascending, cubic Hermite (C1), held at the ends
    glm::dvec3 orbit_center{0.0};    // Orbit: around the vertical axis through orbit_center
    double orbit_radius = 5.0;
    double orbit_height = 1.0;       // eye height above orbit_center
    double orbit_start_deg = 0.0;
    double orbit_deg_per_second = 10.0;
};

struct RenderSettingsPreset {
    std::string method = "auto";  // an exact method: the fastest exact path on the device by default
    double exposure = 0.0;  // PNG exposure, stops
};

struct Preset {
    std::string name;          // "plume", or the file's stem
    std::string description;   // one line, for `brume play --list`
    Scene scene;               // camera (size = resolution), lighting, render, boxes, fixed spheres
    Timeline timeline;
    std::vector<EmitterDesc> emitters;
    std::vector<ForceDesc> forces;
    CameraPath camera_path;
    RenderSettingsPreset render;
    // Read from a document with none of a preset's sections (sim/scene_sections.h kPresetSections):
    // a scene file, a still. play and render --frame refuse it (its 120 frames would be one image);
    // the preview shows it.
    bool still = false;
};

}  // namespace brume
