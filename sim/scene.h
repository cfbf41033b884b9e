// The scene contract (docs/methods.md): what every renderer and method reads.
// Plain data in double precision; the GPU path converts to float when it uploads.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace brume {

// Pixel (i, j), i from the left, j from the top, is the mean of supersample x supersample rays through
// (i + (a + 0.5) / k, j + (b + 0.5) / k), a, b in [0, k); k = 1 is one ray through (i + 0.5, j + 0.5).
struct Camera {
    glm::dvec3 position{0.0, 1.0, 6.0};
    glm::dvec3 look_at{0.0, 0.5, 0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_y_deg = 40.0;  // vertical field of view
    int width = 160;
    int height = 120;
    int supersample = 1;  // k, 1..kMaxSupersample (sim/scene_file.h)
};

struct Lighting {
    glm::dvec3 ambient{0.25, 0.27, 0.30};        // L_ambient
    glm::dvec3 sun{1.0, 0.95, 0.85};             // L_sun, scattered with the Rayleigh phase
    glm::dvec3 sun_direction{-0.4, -1.0, -0.3};  // direction the sunlight travels (need not be unit)
    glm::dvec3 background{0.05, 0.06, 0.08};     // radiance where a ray meets no opaque surface
    // The sun dimmed by the smoke and the boxes on its way in (T_sun, docs/accuracy.md). Off: T_sun = 1, so
    // a scene without the key renders as it did before shadows existed.
    bool shadows = false;
};

// Opaque, axis aligned. Toward the eye: radiance + diffuse * (L_ambient + L_sun max(0, n.l) T_sun(hit)),
// n the normal of the face hit. Solid: an eye inside a box sees radiance + diffuse * L_ambient (no face).
struct Box {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    glm::dvec3 radiance{0.0};
    glm::dvec3 diffuse{0.0};  // reflectance in [0, 1]
};

// One particle: a sphere of homogeneous participating medium.
struct Sphere {
    glm::dvec3 center{0.0};
    double radius = 0.0;
    double extinction = 0.0;  // tau, per scene unit
    glm::dvec3 albedo{1.0};
    // The radiance an optically thick sphere of this medium alone would show by its own light: the
    // medium adds tau * emission per unit length, unshadowed, lighting nothing else.
    glm::dvec3 emission{0.0};
};

// Where a density grid's voxels sit in the scene: world = translate + scale * R * (grid position), R the
// rotations about x, then y, then z, by rotate_deg degrees each. Similarities only, so spheres stay spheres.
struct VolumeTransform {
    glm::dvec3 translate{0.0};
    double scale = 1.0;
    glm::dvec3 rotate_deg{0.0};
};

// Where a density grid comes from: a .vdb file (relative paths against base_dir, the directory of the
// file that names it; empty: the working directory) or "builtin:NAME", a sample volume Brume makes with
// OpenVDB's own API (sim/vdb/vdb_file.h, sample_volumes).
struct DensitySource {
    std::string file;
    std::string base_dir;
    std::string grid = "density";  // the float grid to read
};

// A [[vdb]] table: a density grid loaded as a static cloud of spheres. The scene reader records it and
// sim/vdb/volume_loader.h converts it (brume_sim does not link OpenVDB); renderers see only spheres.
struct VdbVolume {
    DensitySource source;
    // A float grid in the same file multiplying the albedo per sphere. Unset: the file's grid named
    // "albedo" when it has one (what vdb-export writes); "": none; a name: that grid, which must exist.
    std::optional<std::string> albedo_grid;
    double extinction_scale = 1.0;    // sphere extinction = density * extinction_scale, per scene unit
    glm::dvec3 albedo{1.0};
    // The conversion's accuracy: the relative RMS optical-depth error along rays that the sphere cloud
    // must meet (sim/vdb/sphere_cloud.h) ...
    double tolerance = 0.05;
    // ... or, when > 0 (tolerance is then unused), the most accurate cloud of at most this many spheres.
    std::size_t max_spheres = 0;
    // Fit the spheres to the grid (sim/vdb/sphere_fit.h) instead of tiling it: far fewer spheres, a slower
    // conversion (kept in the conversion cache, sim/vdb/conversion_cache.h). max_spheres then caps the fit,
    // with tolerance still its goal.
    bool fit = false;
    VolumeTransform transform;
    // "FILE:LINE" of its [[vdb]] table, which the conversion's messages start with (the file is read well
    // before a volume is converted); "FILE" where the line is not the file's (the preview's edits);
    // empty for a volume built in code.
    std::string defined_at;
};

// How the GPU methods approximate T_sun in the media when the scene has shadows (docs/accuracy.md). The CPU
// reference always computes the exact model.
enum class ShadowTechnique {
    Accurate,   // T_sun sampled by quadrature along each view segment (ppll; others fall back to PerSphere)
    PerSphere,  // T_sun once per sphere, at its centre: the sun term piecewise constant, closed form
};
inline constexpr const char* kShadowTechniqueNames[] = {"accurate", "per-sphere"};

struct RenderSettings {
    // Integration stops once transmittance falls below this (docs/decisions.md); 0 integrates everything.
    double min_transmittance = 1e-4;
    ShadowTechnique shadow_technique = ShadowTechnique::Accurate;
};

struct Scene {
    Camera camera;
    Lighting lighting;
    RenderSettings render;
    std::vector<Box> boxes;
    std::vector<Sphere> spheres;
    std::vector<VdbVolume> volumes;  // not yet converted: renderers require this empty
    // Set by the scene reader when there are volumes and [camera] places neither position nor look_at: the
    // volume loader then aims the camera (keeping its up, field of view and size) so the volumes fill the view.
    bool frame_volumes = false;
    std::string source;  // where the scene came from ("built-in default", a path), for messages
};

}  // namespace brume
