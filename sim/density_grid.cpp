#include "sim/density_grid.h"

#include <glm/common.hpp>

#include <cmath>

namespace brume {

glm::dvec3 DensityGrid::voxel_center(const glm::dvec3& local) const {
    return origin + voxel_size * (glm::dvec3(min) + local);
}

glm::dvec3 DensityGrid::world_min() const { return voxel_center(glm::dvec3(-0.5)); }
glm::dvec3 DensityGrid::world_max() const { return voxel_center(glm::dvec3(size) - 0.5); }
glm::dvec3 DensityGrid::support_min() const { return voxel_center(glm::dvec3(-1.0)); }
glm::dvec3 DensityGrid::support_max() const { return voxel_center(glm::dvec3(size)); }

double DensityGrid::sample(const glm::dvec3& world) const {
    const glm::dvec3 q = (world - origin) / voxel_size - glm::dvec3(min);  // local index space
    const glm::dvec3 base = glm::floor(q);
    const glm::dvec3 f = q - base;
    const int i0 = int(base.x), j0 = int(base.y), k0 = int(base.z);
    if (i0 < -1 || j0 < -1 || k0 < -1 || i0 >= size.x || j0 >= size.y || k0 >= size.z) return 0.0;
    double sum = 0.0;
    for (int dk = 0; dk < 2; ++dk) {
        const int k = k0 + dk;
        if (k < 0 || k >= size.z) continue;
        const double wk = dk ? f.z : 1.0 - f.z;
        for (int dj = 0; dj < 2; ++dj) {
            const int j = j0 + dj;
            if (j < 0 || j >= size.y) continue;
            const double wj = wk * (dj ? f.y : 1.0 - f.y);
            for (int di = 0; di < 2; ++di) {
                const int i = i0 + di;
                if (i < 0 || i >= size.x) continue;
                sum += wj * (di ? f.x : 1.0 - f.x) * double(at(i, j, k));
            }
        }
    }
    return sum;
}

double DensityGrid::mass() const {
    double sum = 0.0;
    for (float v : values) sum += double(v);
    return sum * voxel_size * voxel_size * voxel_size;
}

}  // namespace brume
