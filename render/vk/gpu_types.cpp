#include "render/vk/gpu_types.h"

#include "sim/camera_rays.h"

#include <glm/geometric.hpp>

namespace brume::gpu {
namespace {
vec4 v4(const glm::dvec3& v, double w = 0.0) { return vec4(float(v.x), float(v.y), float(v.z), float(w)); }
}  // namespace

FrameUniforms make_frame_uniforms(const Scene& scene) {
    const CameraRays rays = make_camera_rays(scene.camera);
    FrameUniforms u{};
    u.eye = vec4(0.0f, 0.0f, 0.0f, 0.0f);  // positions are uploaded relative to the eye (gpu_types.h)
    u.forward = v4(rays.forward);
    u.right = v4(rays.right, glm::length(rays.right));
    u.up = v4(rays.up, glm::length(rays.up));
    u.ambient = v4(scene.lighting.ambient);
    u.sun = v4(scene.lighting.sun);
    u.sun_dir = v4(glm::normalize(scene.lighting.sun_direction));
    u.background = v4(scene.lighting.background);
    u.counts = uvec4(uint(scene.camera.width), uint(scene.camera.height), uint(scene.spheres.size()),
                     uint(scene.boxes.size()));
    const bool accurate = scene.lighting.shadows && scene.render.shadow_technique == ShadowTechnique::Accurate;
    u.params = vec4(float(scene.render.min_transmittance), 0.0f, scene.lighting.shadows ? 1.0f : 0.0f,
                    accurate ? 1.0f : 0.0f);
    return u;
}

GpuSphere to_gpu(const Sphere& s, const glm::dvec3& eye, double sun_transmittance) {
    return GpuSphere{v4(s.center - eye, s.radius), v4(s.albedo, s.extinction), v4(s.emission, sun_transmittance)};
}

GpuBox to_gpu(const Box& b, const glm::dvec3& eye) {
    return GpuBox{v4(b.min - eye), v4(b.max - eye), v4(b.radiance), v4(b.diffuse)};
}

}  // namespace brume::gpu
