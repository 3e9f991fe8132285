#include "ui/overlay_geometry.h"

#include <cmath>
#include <cstdint>

namespace caustica::ui {
namespace {

constexpr double pi = 3.14159265358979323846;
/// A segment longer than this many cell widths (at its distance from the light) joins two
/// surfaces, not one: rays 1 cell apart only land this far apart beyond ~83 degrees of incidence.
constexpr float max_cell_stretch = 8.0f;

/// Picks each grid corner at most once.
class CornerHits {
public:
    CornerHits(const LightProjectionMap& map, const PickFunction& pick)
        : map_(map), pick_(pick), state_(static_cast<std::size_t>(map.map.rows() + 1) * map.map.columns(), 0),
          points_(state_.size()) {}

    /// The surface point seen from the light through corner (row, column), or false.
    bool point(int row, int column, glm::vec3& p) {
        const std::size_t i = static_cast<std::size_t>(row) * map_.map.columns() + column;
        if (state_[i] == 0) {
            const Ray ray{map_.light_position, grid_corner_direction(map_.map, row, column), 0.0f, ray_infinity};
            state_[i] = pick_(ray, points_[i]) ? 1 : 2;
        }
        p = points_[i];
        return state_[i] == 1;
    }

private:
    const LightProjectionMap& map_;
    const PickFunction& pick_;
    std::vector<std::uint8_t> state_;  // 0 = not traced, 1 = hit, 2 = miss
    std::vector<glm::vec3> points_;
};

void add_quad(std::vector<OverlayVertex>& out, glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 d, glm::vec4 colour) {
    for (glm::vec2 p : {a, b, c, a, c, d}) out.push_back({p, colour});
}

void add_square(std::vector<OverlayVertex>& out, glm::vec2 centre, float size, glm::vec4 colour) {
    const float h = 0.5f * size;
    add_quad(out, centre + glm::vec2(-h, -h), centre + glm::vec2(h, -h), centre + glm::vec2(h, h),
             centre + glm::vec2(-h, h), colour);
}

/// Whether a surface lies between the eye and a point (false without a pick function).
bool hidden_from(const glm::vec3& eye, const glm::vec3& point, const PickFunction& pick) {
    if (!pick) return false;
    const float distance = glm::length(point - eye);
    glm::vec3 p;
    return distance > 0.0f && pick(Ray{eye, (point - eye) / distance, 0.0f, 0.99f * distance}, p);
}

}  // namespace

glm::vec3 grid_corner_direction(const ProjectionMap& map, int row, int column) {
    const double theta = row * pi / map.rows();
    const double phi = column * 2.0 * pi / map.columns();
    return glm::vec3(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                     static_cast<float>(std::sin(theta) * std::sin(phi)));
}

OverlayWorld trace_overlay(const LightProjectionMap& light, const PickFunction& pick, bool with_cells) {
    OverlayWorld world;
    world.light_index = light.light_index;
    world.light_position = light.light_position;
    const ProjectionMap& map = light.map;
    if (map.empty()) return world;
    const int rows = map.rows(), columns = map.columns();
    const float cell_angle = static_cast<float>(pi / rows);
    CornerHits corners(light, pick);
    auto add_edge = [&](int r0, int c0, int r1, int c1) {
        ++world.boundary_edges;
        glm::vec3 a, b;
        if (!corners.point(r0, c0 % columns, a) || !corners.point(r1, c1 % columns, b)) return;
        const float reach = std::max(glm::length(a - light.light_position), glm::length(b - light.light_position));
        if (glm::length(b - a) > max_cell_stretch * cell_angle * reach) return;
        world.outline.push_back(a);
        world.outline.push_back(b);
    };
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c) {
            const bool here = map.cell(r, c);
            if (here != map.cell(r, (c + 1) % columns)) add_edge(r, c + 1, r + 1, c + 1);  // between columns
            if (r + 1 < rows && here != map.cell(r + 1, c)) add_edge(r + 1, c, r + 1, c + 1);  // between rows
        }
    if (with_cells)
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < columns; ++c) {
                glm::vec3 p;
                if (map.cell(r, c) && pick(Ray{light.light_position, map.cell_centre(r, c), 0.0f, ray_infinity}, p))
                    world.cells.push_back(p);
            }
    return world;
}

OverlayImage project_overlay(const OverlayWorld& world, const Camera& camera, const glm::vec3& eye,
                             const PickFunction& pick) {
    OverlayImage image;
    for (std::size_t i = 0; i + 1 < world.outline.size(); i += 2) {
        glm::vec2 a, b;
        if (!camera.project(world.outline[i], a) || !camera.project(world.outline[i + 1], b)) continue;
        image.outline.push_back(a);
        image.outline.push_back(b);
        image.hidden.push_back(hidden_from(eye, 0.5f * (world.outline[i] + world.outline[i + 1]), pick) ? 1 : 0);
    }
    for (const glm::vec3& p : world.cells) {
        glm::vec2 q;
        if (!camera.project(p, q)) continue;
        image.cells.push_back(q);
        image.cells_hidden.push_back(hidden_from(eye, p, pick) ? 1 : 0);
    }
    image.light_visible = camera.project(world.light_position, image.light);
    return image;
}

std::vector<OverlayVertex> overlay_triangles(const OverlayImage& image, const OverlayStyle& style) {
    std::vector<OverlayVertex> out;
    out.reserve(6 * (image.outline.size() / 2 + image.cells.size() + 2));
    for (std::size_t i = 0; i < image.cells.size(); ++i) {
        const bool hidden = i < image.cells_hidden.size() && image.cells_hidden[i];
        add_square(out, image.cells[i], style.cell_size, hidden ? style.hidden_cell_colour : style.cell_colour);
    }
    const float h = 0.5f * style.line_width;
    for (std::size_t i = 0; i + 1 < image.outline.size(); i += 2) {
        const glm::vec2 a = image.outline[i], b = image.outline[i + 1];
        const glm::vec2 d = b - a;
        const float length = glm::length(d);
        // Extend each end by half the width, so that consecutive segments join without gaps.
        const glm::vec2 along = length > 1e-6f ? d / length * h : glm::vec2(h, 0.0f);
        const glm::vec2 across(-along.y, along.x);
        const bool hidden = i / 2 < image.hidden.size() && image.hidden[i / 2];
        add_quad(out, a - along - across, b + along - across, b + along + across, a - along + across,
                 hidden ? style.hidden_colour : style.outline_colour);
    }
    if (image.light_visible) {
        add_square(out, image.light, 4.0f * style.line_width, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        add_square(out, image.light, 2.0f * style.line_width, style.light_colour);
    }
    return out;
}

}  // namespace caustica::ui
