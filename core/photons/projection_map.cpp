#include "core/photons/projection_map.h"

#include "core/util/cancel_flag.h"
#include "core/util/denormals.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {
constexpr double pi = 3.14159265358979323846;
}

ProjectionMap::ProjectionMap(int granularity)
    : rows_(granularity), columns_(2 * granularity), cells_(static_cast<std::size_t>(rows_) * columns_, 0) {
    row_bounds_.resize(static_cast<std::size_t>(rows_));
    row_count_.assign(static_cast<std::size_t>(rows_), 0);
    for (int row = 0; row < rows_; ++row) row_bounds_[row] = static_cast<float>(0.5 * (1.0 - std::cos(row * pi / rows_)));
}

std::size_t ProjectionMap::cell_of(const glm::vec3& d) const {
    const double theta = std::acos(std::clamp(static_cast<double>(d.y), -1.0, 1.0));
    double phi = std::atan2(static_cast<double>(d.z), static_cast<double>(d.x));
    if (phi < 0.0) phi += 2.0 * pi;
    const int row = std::min(rows_ - 1, static_cast<int>(theta / pi * rows_));
    const int column = std::min(columns_ - 1, static_cast<int>(phi / (2.0 * pi) * columns_));
    return static_cast<std::size_t>(row) * columns_ + column;
}

glm::vec3 ProjectionMap::cell_centre(int row, int column) const {
    const double theta = (row + 0.5) * pi / rows_;
    const double phi = (column + 0.5) * 2.0 * pi / columns_;
    return glm::vec3(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                     static_cast<float>(std::sin(theta) * std::sin(phi)));
}

double ProjectionMap::cell_solid_angle(int row) const {
    const double theta0 = row * pi / rows_, theta1 = (row + 1) * pi / rows_;
    return (2.0 * pi / columns_) * (std::cos(theta0) - std::cos(theta1));
}

void ProjectionMap::build(const RenderScene& scene, const glm::vec3& light, bool (*target)(const Material&),
                          const std::atomic<bool>* cancel) {
    std::vector<std::uint8_t> hits(cells_.size(), 0);
    const auto& materials = scene.materials();
    caustica::parallel_for(tbb::blocked_range<int>(0, rows_), [&](const tbb::blocked_range<int>& range) {
        const ScopedFlushDenormals flush;
        for (int row = range.begin(); row != range.end(); ++row) {
            if (is_cancelled(cancel)) return;
            for (int column = 0; column < columns_; ++column) {
                SurfaceHit hit;
                if (!scene.intersect(Ray{light, cell_centre(row, column), 0.0f, ray_infinity}, hit, cancel)) continue;
                const Material& m = materials[hit.material];
                const bool is_target = target ? target(m) : (m.reflective || m.transparent);
                if (is_target) hits[static_cast<std::size_t>(row) * columns_ + column] = 1;
            }
        }
    });
    // Set the neighbours too, so that objects between sample directions are not missed.
    for (int row = 0; row < rows_; ++row)
        for (int column = 0; column < columns_; ++column) {
            if (!hits[static_cast<std::size_t>(row) * columns_ + column]) continue;
            for (int dr = -1; dr <= 1; ++dr) {
                const int r = row + dr;
                if (r < 0 || r >= rows_) continue;
                for (int dc = -1; dc <= 1; ++dc) set_cell(r, (column + dc + columns_) % columns_, true);
            }
        }
}

bool ProjectionMap::any_occupied_between(double u0, double u1) const {
    if (u1 - u0 >= 1.0) u0 = 0.0, u1 = 1.0;
    auto row_of = [&](double u) {
        const auto r = std::upper_bound(row_bounds_.begin(), row_bounds_.end(), static_cast<float>(u)) - row_bounds_.begin() - 1;
        return std::clamp(static_cast<int>(r), 0, rows_ - 1);
    };
    auto any_rows = [&](double a, double b) {
        for (int r = row_of(a), last = row_of(b); r <= last; ++r)
            if (row_count_[r] > 0) return true;
        return false;
    };
    if (u1 <= 1.0) return any_rows(u0, u1);
    return any_rows(u0, 1.0) || any_rows(0.0, u1 - 1.0);
}

OccupiedCells::OccupiedCells(const ProjectionMap& map) {
    for (int row = 0; row < map.rows(); ++row) {
        const double theta0 = row * pi / map.rows(), theta1 = (row + 1) * pi / map.rows();
        const double share = map.cell_solid_angle(row) / (4.0 * pi);
        for (int column = 0; column < map.columns(); ++column) {
            if (!map.cell(row, column)) continue;
            const double phi0 = column * 2.0 * pi / map.columns(), phi1 = (column + 1) * 2.0 * pi / map.columns();
            cells_.push_back({std::cos(theta0), std::cos(theta1), phi0, phi1, share});
            fraction_ += share;
        }
    }
}

glm::vec3 OccupiedCells::direction(std::size_t cell, double s, double t) const {
    const Cell& c = cells_[cell];
    const double y = c.cos_theta0 + s * (c.cos_theta1 - c.cos_theta0);
    const double phi = c.phi0 + t * (c.phi1 - c.phi0);
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    return glm::vec3(static_cast<float>(r * std::cos(phi)), static_cast<float>(y), static_cast<float>(r * std::sin(phi)));
}

double ProjectionMap::occupied_fraction() const {
    double occupied = 0.0;
    for (int row = 0; row < rows_; ++row) {
        int count = 0;
        for (int column = 0; column < columns_; ++column) count += cell(row, column);
        occupied += count * cell_solid_angle(row);
    }
    return occupied / (4.0 * pi);
}

}  // namespace caustica
