// The projection-map overlay as geometry: where a light's map outline and occupied cells fall on
// the scene (rays from the light, traced once per map), their image positions under the current
// camera (per camera change), and the triangles that draw them (no GL here).
#pragma once

#include "core/scene/camera.h"
#include "core/render/render_session.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace caustica::ui {

/// Finds the first surface point along a ray (RenderSession::pick).
using PickFunction = std::function<bool(const Ray&, glm::vec3&)>;

/// One light's projection map traced onto the scene, in world space.
struct OverlayWorld {
    int light_index = -1;
    glm::vec3 light_position{0.0f};
    std::vector<glm::vec3> outline;  ///< segment end points, two per segment
    std::vector<glm::vec3> cells;    ///< surface points of occupied cell centres
    int boundary_edges = 0;          ///< edges between occupied and free cells (some may miss the scene)
};

/// The unit direction of the map's grid corner (row, column): theta = row pi / rows from +y,
/// phi = column 2 pi / columns from +x towards +z.
glm::vec3 grid_corner_direction(const ProjectionMap& map, int row, int column);

/// Traces the boundary between occupied and free cells (each edge's two corner directions) and,
/// when `with_cells`, every occupied cell centre onto the scene. A segment whose ends land on
/// different surfaces (far longer than a cell there) is left out.
OverlayWorld trace_overlay(const LightProjectionMap& map, const PickFunction& pick, bool with_cells);

/// The overlay in image pixels.
struct OverlayImage {
    std::vector<glm::vec2> outline;        ///< two points per segment
    std::vector<std::uint8_t> hidden;      ///< per segment: 1 when something is in front of it
    std::vector<glm::vec2> cells;
    std::vector<std::uint8_t> cells_hidden;  ///< per cell: 1 when something is in front of it
    bool light_visible = false;
    glm::vec2 light{0.0f};
};

/// Projects the traced overlay with a camera (segments with an end behind the eye are dropped).
/// With `pick`, a segment whose midpoint (a cell whose point) is hidden from `eye` by a surface
/// is marked hidden.
OverlayImage project_overlay(const OverlayWorld& world, const Camera& camera, const glm::vec3& eye = glm::vec3(0.0f),
                             const PickFunction& pick = nullptr);

/// One vertex of the overlay's triangles.
struct OverlayVertex {
    glm::vec2 position;  ///< image pixels
    glm::vec4 colour;
};

/// Sizes and colours of the drawn overlay, in image pixels.
struct OverlayStyle {
    float line_width = 2.0f;
    float cell_size = 3.0f;
    glm::vec4 outline_colour{1.0f, 0.85f, 0.1f, 1.0f};
    glm::vec4 hidden_colour{1.0f, 0.85f, 0.1f, 0.35f};  ///< segments behind a surface
    glm::vec4 cell_colour{1.0f, 0.35f, 0.1f, 0.7f};
    glm::vec4 hidden_cell_colour{1.0f, 0.35f, 0.1f, 0.2f};
    glm::vec4 light_colour{1.0f, 1.0f, 1.0f, 1.0f};
};

/// Triangles (three vertices each) drawing every segment as a quad and every cell as a square.
std::vector<OverlayVertex> overlay_triangles(const OverlayImage& image, const OverlayStyle& style);

}  // namespace caustica::ui
