#include "sim/volume_transform.h"

#include "sim/scene_file.h"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <cmath>

namespace brume {

glm::dmat3 volume_rotation(const VolumeTransform& t) {
    const glm::dvec3 r = t.rotate_deg * (3.14159265358979323846 / 180.0);
    const double cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y);
    const double cz = std::cos(r.z), sz = std::sin(r.z);
    // glm matrices are column-major: each dvec3 below is a column.
    const glm::dmat3 rx({1, 0, 0}, {0, cx, sx}, {0, -sx, cx});
    const glm::dmat3 ry({cy, 0, -sy}, {0, 1, 0}, {sy, 0, cy});
    const glm::dmat3 rz({cz, sz, 0}, {-sz, cz, 0}, {0, 0, 1});
    return rz * ry * rx;
}

glm::dvec3 volume_to_world(const VolumeTransform& t, const glm::dvec3& p) {
    return t.translate + t.scale * (volume_rotation(t) * p);
}

glm::dvec3 world_to_volume(const VolumeTransform& t, const glm::dvec3& p) {
    return (glm::transpose(volume_rotation(t)) * (p - t.translate)) / t.scale;
}

Sphere volume_to_world(const VolumeTransform& t, const Sphere& s) {
    Sphere out = s;
    out.center = volume_to_world(t, s.center);
    out.radius = s.radius * t.scale;
    return out;
}

std::string volume_transform_problem(const VolumeTransform& t) {
    using toml_text::shortest;
    if (!(std::isfinite(t.scale) && t.scale > 0.0 && t.scale <= kMaxCoordinate))
        return "scale must be positive, finite and at most " + shortest(kMaxCoordinate) + " (got " + shortest(t.scale) + ")";
    for (int a = 0; a < 3; ++a) {
        if (!(std::abs(t.translate[a]) <= kMaxCoordinate))
            return "translate components must be finite, at most " + shortest(kMaxCoordinate) + " in size (got " +
                   shortest(t.translate[a]) + ")";
        if (!(std::abs(t.rotate_deg[a]) <= 3600.0))
            return "rotate components must be finite degrees, at most 3600 in size (got " + shortest(t.rotate_deg[a]) + ")";
    }
    return {};
}

}  // namespace brume
