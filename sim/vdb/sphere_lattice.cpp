#include "sim/vdb/sphere_lattice.h"

#include "sim/vdb/sphere_cloud.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brume {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Integral over [a, b] of the unit tent centred at 0 (1 - |x| on [-1, 1]).
double tent_integral(double a, double b) {
    const auto cdf = [](double x) {  // integral from -1 to x
        x = std::clamp(x, -1.0, 1.0);
        return x <= 0.0 ? 0.5 * (1.0 + x) * (1.0 + x) : 1.0 - 0.5 * (1.0 - x) * (1.0 - x);
    };
    return cdf(b) - cdf(a);
}

// Along one axis of n voxels: for each of `cells` cells [start + c * spacing, start + (c + 1) * spacing] (in
// voxel-centre index units), the voxels whose tents reach it and the length of tent inside it.
struct AxisWeights {
    std::vector<int> first;                  // per cell: the first voxel
    std::vector<std::vector<double>> weight;  // per cell: per voxel from `first`
};

AxisWeights axis_weights(int n, int cells, double start, double spacing) {
    AxisWeights w;
    w.first.resize(std::size_t(cells));
    w.weight.resize(std::size_t(cells));
    for (int c = 0; c < cells; ++c) {
        const double a = start + c * spacing, b = a + spacing;
        const int lo = std::max(0, int(std::floor(a - 1.0))), hi = std::min(n - 1, int(std::ceil(b + 1.0)));
        w.first[std::size_t(c)] = lo;
        for (int i = lo; i <= hi; ++i) w.weight[std::size_t(c)].push_back(tent_integral(a - i, b - i));
    }
    return w;
}

}  // namespace

std::vector<Sphere> grid_to_lattice_spheres(const DensityGrid& grid, const SphereCloudOptions& options, double spacing) {
    if (!(spacing > 1.0) || !std::isfinite(spacing))
        throw std::invalid_argument("lattice spacing must exceed one voxel (got " + std::to_string(spacing) + ")");
    // The field's support in index units is [-1, size]; the lattice starts there and covers it.
    glm::ivec3 cells;
    for (int a = 0; a < 3; ++a) cells[a] = std::max(1, int(std::ceil((grid.size[a] + 1) / spacing)));
    AxisWeights w[3];
    for (int a = 0; a < 3; ++a) w[a] = axis_weights(grid.size[a], cells[a], -1.0, spacing);

    // Separable integration: x first (cells.x by ny by nz), then y, then z.
    const std::size_t ny = std::size_t(grid.size.y), nz = std::size_t(grid.size.z);
    const std::size_t cx = std::size_t(cells.x), cy = std::size_t(cells.y), cz = std::size_t(cells.z);
    std::vector<double> along_x(cx * ny * nz, 0.0);
    for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t j = 0; j < ny; ++j) {
            const float* row = &grid.values[grid.offset(0, int(j), int(k))];
            for (std::size_t c = 0; c < cx; ++c) {
                double sum = 0.0;
                const std::vector<double>& wc = w[0].weight[c];
                for (std::size_t t = 0; t < wc.size(); ++t) sum += wc[t] * row[std::size_t(w[0].first[c]) + t];
                along_x[(k * ny + j) * cx + c] = sum;
            }
        }
    std::vector<double> along_xy(cx * cy * nz, 0.0);
    for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t c = 0; c < cy; ++c) {
            const std::vector<double>& wc = w[1].weight[c];
            for (std::size_t t = 0; t < wc.size(); ++t) {
                const std::size_t j = std::size_t(w[1].first[c]) + t;
                for (std::size_t i = 0; i < cx; ++i) along_xy[(k * cy + c) * cx + i] += wc[t] * along_x[(k * ny + j) * cx + i];
            }
        }
    const double voxel_volume = grid.voxel_size * grid.voxel_size * grid.voxel_size;
    const double cell_volume = spacing * spacing * spacing * voxel_volume;
    const double radius = options.sphere_scale * std::cbrt(3.0 * cell_volume / (4.0 * kPi));
    const double sphere_volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    std::vector<Sphere> spheres;
    std::vector<double> mass(cx * cy);
    for (std::size_t c = 0; c < cz; ++c) {
        std::fill(mass.begin(), mass.end(), 0.0);
        const std::vector<double>& wc = w[2].weight[c];
        for (std::size_t t = 0; t < wc.size(); ++t) {
            const std::size_t k = std::size_t(w[2].first[c]) + t;
            for (std::size_t ij = 0; ij < cx * cy; ++ij) mass[ij] += wc[t] * along_xy[k * cx * cy + ij];
        }
        for (std::size_t b = 0; b < cy; ++b)
            for (std::size_t a = 0; a < cx; ++a) {
                const double m = mass[b * cx + a] * voxel_volume;  // integral of density over the cell
                if (!(m > 0.0)) continue;
                const glm::dvec3 centre_index = glm::dvec3(-1.0) + spacing * (glm::dvec3(double(a), double(b), double(c)) + 0.5);
                Sphere s;
                s.center = grid.voxel_center(centre_index);
                s.radius = radius;
                s.extinction = m * options.extinction_scale / sphere_volume;
                s.albedo = options.albedo;
                if (options.albedo_grid)
                    s.albedo *= std::clamp(options.albedo_grid->sample(s.center), 0.0, 1.0);
                spheres.push_back(s);
            }
    }
    return spheres;
}

}  // namespace brume
