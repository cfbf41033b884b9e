#include "sim/density_sampler.h"

#include "sim/scene_file.h"
#include "sim/volume_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace brume {

DensitySampler::DensitySampler(DensityGrid grid, const VolumeTransform& transform)
    : grid_(std::move(grid)), transform_(transform) {
    if (const std::string problem = volume_transform_problem(transform_); !problem.empty())
        throw std::invalid_argument("density sampler: " + problem);
    if (grid_.voxel_count() > std::numeric_limits<std::uint32_t>::max())
        throw std::invalid_argument("density sampler: grid " + toml_text::quoted(grid_.name) +
                                    " has more than 2^32 voxels");
    double sum = 0.0;
    for (std::size_t i = 0; i < grid_.voxel_count(); ++i) {
        const double v = grid_.values[i];
        if (!(v > 0.0)) continue;
        sum += v;
        voxels_.push_back(std::uint32_t(i));
        cdf_.push_back(sum);
    }
    if (!(sum > 0.0) || !std::isfinite(sum))
        throw std::invalid_argument("density sampler: grid " + toml_text::quoted(grid_.name) +
                                    " holds no positive density");
}

double DensitySampler::mass() const { return cdf_.back() * grid_.voxel_size * grid_.voxel_size * grid_.voxel_size; }

double tent_offset(double u) {
    // The CDF is (1 + t)^2 / 2 on [-1, 0] and 1 - (1 - t)^2 / 2 on [0, 1]; each half inverted.
    return u < 0.5 ? std::sqrt(2.0 * u) - 1.0 : 1.0 - std::sqrt(2.0 * (1.0 - u));
}

glm::dvec3 DensitySampler::sample(double u0, double u1, double u2, double u3) const {
    // The first running sum above u0 * total: voxel n is picked for u0 * total in [cdf[n-1], cdf[n]),
    // an interval as long as its value. The clamp covers u0 * total rounding up to the total itself.
    const double target = u0 * cdf_.back();
    const std::size_t n = std::min<std::size_t>(
        std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin()), cdf_.size() - 1);
    const std::size_t offset = voxels_[n];
    const std::size_t sx = std::size_t(grid_.size.x), sy = std::size_t(grid_.size.y);
    const glm::dvec3 voxel{double(offset % sx), double((offset / sx) % sy), double(offset / (sx * sy))};
    const glm::dvec3 local = voxel + glm::dvec3{tent_offset(u1), tent_offset(u2), tent_offset(u3)};
    return volume_to_world(transform_, grid_.voxel_center(local));
}

}  // namespace brume
