// Light projection maps (docs/CAUSTICS.md, "Projection maps"): a bit per cell of a polar (theta,
// phi) map of directions around a light, set where a ray from the light hits a specular object (and
// around such cells), so that photons are shot only where they can become caustics.
#pragma once

#include "core/geometry/render_scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

namespace caustica {

/// The polar cell grid: `granularity` rows of theta in [0, pi], 2 x granularity columns of phi.
class ProjectionMap {
public:
    ProjectionMap() = default;
    explicit ProjectionMap(int granularity);

    /// Shoots one ray per cell centre from `light`; sets cells whose first hit is a target, and
    /// their eight neighbours. Runs in parallel. Targets: reflective or transparent surfaces, or
    /// the materials `target` accepts when given (the classic rule, classic_projection_target).
    /// Stops between rows once `cancel` (null: none) is set: the map is then incomplete.
    void build(const RenderScene& scene, const glm::vec3& light, bool (*target)(const Material&) = nullptr,
               const std::atomic<bool>* cancel = nullptr);

    /// Whether the cell containing a unit direction is set.
    bool occupied(const glm::vec3& direction) const { return cells_[cell_of(direction)] != 0; }

    /// Whether the cell of the direction sphere_direction(u, v) is set (y = 1 - 2u, phi = 2 pi v),
    /// found without trigonometry: the photon loop asks this for every candidate direction.
    bool occupied_uv(float u, float v) const {
        const auto row = static_cast<int>(std::upper_bound(row_bounds_.begin(), row_bounds_.end(), u) - row_bounds_.begin()) - 1;
        const int column = std::min(columns_ - 1, static_cast<int>(v * static_cast<float>(columns_)));
        return cells_[static_cast<std::size_t>(std::clamp(row, 0, rows_ - 1)) * columns_ + column] != 0;
    }

    /// Whether any cell is set in the rows that u in [u0, u1] covers (u1 may exceed 1: wraps).
    bool any_occupied_between(double u0, double u1) const;

    /// Occupied solid angle over 4 pi, with each cell weighted by its true (non-uniform) area.
    double occupied_fraction() const;

    /// Cell index of a unit direction.
    std::size_t cell_of(const glm::vec3& direction) const;
    /// The unit direction through a cell's centre.
    glm::vec3 cell_centre(int row, int column) const;
    /// Solid angle of a cell in row `row` (all cells of a row have the same).
    double cell_solid_angle(int row) const;

    int rows() const { return rows_; }
    int columns() const { return columns_; }
    bool cell(int row, int column) const { return cells_[static_cast<std::size_t>(row) * columns_ + column] != 0; }
    void set_cell(int row, int column, bool value) {
        cells_[static_cast<std::size_t>(row) * columns_ + column] = value;
        row_count_[row] += value ? 1 : 0;  // an upper bound: clearing a cell leaves the row marked
    }
    bool empty() const { return cells_.empty(); }

private:
    int rows_ = 0, columns_ = 0;
    std::vector<std::uint8_t> cells_;
    std::vector<float> row_bounds_;  ///< u = (1 - cos theta) / 2 where each row starts
    std::vector<int> row_count_;     ///< cells set in each row (upper bound)
};

/// A projection map's occupied cells as a list to shoot photons into: a photon pass traces every
/// direction it draws instead of drawing over the whole sphere and rejecting the directions outside
/// the map. Each cell gets its share of the photons (its solid angle over 4 pi), placed in an even
/// pattern inside it.
class OccupiedCells {
public:
    struct Cell {
        double cos_theta0, cos_theta1, phi0, phi1;
        double share;  ///< solid angle over 4 pi
    };

    explicit OccupiedCells(const ProjectionMap& map);

    /// Solid angle of the occupied cells over 4 pi.
    double fraction() const { return fraction_; }
    const std::vector<Cell>& cells() const { return cells_; }

    /// The direction at (s, t) of the unit square mapped onto cell `cell`, uniform in solid angle:
    /// s runs over cos theta, t over phi.
    glm::vec3 direction(std::size_t cell, double s, double t) const;

private:
    std::vector<Cell> cells_;
    double fraction_ = 0.0;
};

}  // namespace caustica
