// The projection-map overlay geometry: the outline follows the boundary between occupied and
// free cells, lands where the light's rays hit the scene, and projects into the image.
#include "ui/overlay_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace caustica::ui {
namespace {

/// A light at height 1 above the plane y = 0: every downward ray hits it.
bool pick_floor(const Ray& ray, glm::vec3& point) {
    if (ray.direction.y >= 0.0f) return false;
    const float t = -ray.origin.y / ray.direction.y;
    point = ray.origin + t * ray.direction;
    return true;
}

/// A map with a block of rows [r0, r1) x columns [c0, c1) occupied.
LightProjectionMap block_map(int granularity, int r0, int r1, int c0, int c1) {
    LightProjectionMap m{ProjectionMap(granularity), glm::vec3(0.0f, 1.0f, 0.0f), 0};
    for (int r = r0; r < r1; ++r)
        for (int c = c0; c < c1; ++c) m.map.set_cell(r, c, true);
    return m;
}

TEST(OverlayGeometry, CornerDirectionsBoundTheirCells) {
    const ProjectionMap map(18);
    // The centre of cell (r, c) lies between its corners (r, c) and (r + 1, c + 1).
    const glm::vec3 centre = map.cell_centre(12, 7);
    const glm::vec3 a = grid_corner_direction(map, 12, 7), b = grid_corner_direction(map, 13, 8);
    EXPECT_GT(std::acos(a.y), 0.0f);
    EXPECT_LT(std::acos(a.y), std::acos(centre.y));
    EXPECT_LT(std::acos(centre.y), std::acos(b.y));
    EXPECT_EQ(map.cell_of(glm::normalize(0.5f * (a + b))), map.cell_of(centre));
    EXPECT_NEAR(glm::length(a), 1.0f, 1e-6f);
}

TEST(OverlayGeometry, OutlineIsTheBoundaryOfTheOccupiedBlock) {
    // Rows 60..69 (theta 120..140 degrees: below the horizon), columns 30..44: a 10 x 15 block
    // has 2 x (10 + 15) boundary edges.
    const LightProjectionMap map = block_map(90, 60, 70, 30, 45);
    const OverlayWorld world = trace_overlay(map, pick_floor, true);
    EXPECT_EQ(world.boundary_edges, 2 * (10 + 15));
    EXPECT_EQ(world.outline.size(), 2u * 50u);  // every edge hits the floor
    EXPECT_EQ(world.cells.size(), 150u);
    // Every outline point is on the floor and seen from the light along a corner direction of the
    // block's boundary: its direction's cell is next to an occupied and a free cell.
    for (const glm::vec3& p : world.outline) {
        EXPECT_NEAR(p.y, 0.0f, 1e-5f);
        const glm::vec3 d = glm::normalize(p - map.light_position);
        const double theta = std::acos(d.y), phi = std::atan2(d.z, d.x);
        const double row = theta / (M_PI / 90.0), column = (phi < 0 ? phi + 2 * M_PI : phi) / (M_PI / 90.0);
        EXPECT_GE(row, 60.0 - 1e-3);
        EXPECT_LE(row, 70.0 + 1e-3);
        EXPECT_GE(column, 30.0 - 1e-3);
        EXPECT_LE(column, 45.0 + 1e-3);
        const bool on_row_edge = std::abs(row - 60.0) < 1e-3 || std::abs(row - 70.0) < 1e-3;
        const bool on_column_edge = std::abs(column - 30.0) < 1e-3 || std::abs(column - 45.0) < 1e-3;
        EXPECT_TRUE(on_row_edge || on_column_edge) << row << " " << column;
    }
}

TEST(OverlayGeometry, OutlineWrapsAroundPhi) {
    // Columns 170..179 and 0..9 of a granularity-90 map form one block across phi = 0.
    LightProjectionMap map = block_map(90, 60, 62, 170, 180);
    for (int r = 60; r < 62; ++r)
        for (int c = 0; c < 10; ++c) map.map.set_cell(r, c, true);
    const OverlayWorld world = trace_overlay(map, pick_floor, false);
    EXPECT_EQ(world.boundary_edges, 2 * (2 + 20));  // no edge at phi = 0
    EXPECT_TRUE(world.cells.empty());
}

TEST(OverlayGeometry, SegmentsJoiningTwoSurfacesAreLeftOut) {
    const LightProjectionMap map = block_map(90, 60, 70, 30, 45);
    // A shelf at height 0.6 over the floor where x > 0.3: corners on either side of its edge
    // land on different surfaces, far apart.
    auto pick = [](const Ray& ray, glm::vec3& point) {
        if (ray.direction.y < 0.0f) {
            const glm::vec3 p = ray.origin + (0.6f - ray.origin.y) / ray.direction.y * ray.direction;
            if (p.x > 0.3f) {
                point = p;
                return true;
            }
        }
        return pick_floor(ray, point);
    };
    const OverlayWorld world = trace_overlay(map, pick, false);
    const float cell = static_cast<float>(M_PI / 90.0);
    for (std::size_t i = 0; i < world.outline.size(); i += 2) {
        const float reach = std::max(glm::length(world.outline[i] - map.light_position),
                                     glm::length(world.outline[i + 1] - map.light_position));
        EXPECT_LE(glm::length(world.outline[i + 1] - world.outline[i]), 8.0f * cell * reach);
    }
    EXPECT_LT(world.outline.size(), 2u * 50u);
}

TEST(OverlayGeometry, ProjectionUsesTheCameraAndDropsPointsBehindIt) {
    OverlayWorld world;
    world.light_position = {0.0f, 1.0f, 0.0f};
    world.outline = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 10.0f}, {1.0f, 0.0f, 10.0f}};
    world.cells = {{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 9.0f}};
    CameraDesc desc;
    desc.eye = {0.0, 0.0, 5.0};
    desc.view = {0.0, 0.0, -1.0};
    desc.fovy_degrees = 90.0;
    const Camera camera(desc, 100, 100);
    const OverlayImage image = project_overlay(world, camera);
    ASSERT_EQ(image.outline.size(), 2u);  // the second segment is behind the eye
    EXPECT_NEAR(image.outline[0].x, 50.0f, 1e-4f);
    EXPECT_NEAR(image.outline[0].y, 50.0f, 1e-4f);
    EXPECT_NEAR(image.outline[1].x, 60.0f, 1e-4f);  // 1 unit at depth 5 with tan(45) = 1: 50 / 5 pixels
    ASSERT_EQ(image.cells.size(), 1u);
    EXPECT_TRUE(image.light_visible);
    EXPECT_NEAR(image.light.y, 40.0f, 1e-4f);
}

TEST(OverlayGeometry, SegmentsBehindASurfaceAreMarkedHidden) {
    OverlayWorld world;
    world.outline = {{-1.0f, 0.0f, 0.0f}, {-0.5f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
    world.light_position = {0.0f, 0.0f, 10.0f};  // behind the eye: no light marker
    CameraDesc desc;
    desc.eye = {0.0, 0.0, 5.0};
    desc.view = {0.0, 0.0, -1.0};
    const Camera camera(desc, 100, 100);
    // A blocker at z = 2 covering x < 0: it hides the left segment only. Rays stop short of
    // the segments themselves (tmax), so the floor they lie on does not hide them.
    auto pick = [](const Ray& ray, glm::vec3& p) {
        const float t = (2.0f - ray.origin.z) / ray.direction.z;
        p = ray.origin + t * ray.direction;
        return t > ray.tmin && t < ray.tmax && p.x < 0.0f;
    };
    const OverlayImage image = project_overlay(world, camera, glm::vec3(desc.eye), pick);
    ASSERT_EQ(image.hidden.size(), 2u);
    EXPECT_EQ(image.hidden[0], 1);
    EXPECT_EQ(image.hidden[1], 0);
    const OverlayStyle style;
    const std::vector<OverlayVertex> triangles = overlay_triangles(image, style);
    ASSERT_EQ(triangles.size(), 12u);
    EXPECT_EQ(triangles[0].colour, style.hidden_colour);
    EXPECT_EQ(triangles[6].colour, style.outline_colour);
}

TEST(OverlayGeometry, TrianglesCoverSegmentsAndCells) {
    OverlayImage image;
    image.outline = {{10.0f, 10.0f}, {20.0f, 10.0f}};
    image.cells = {{5.0f, 5.0f}};
    OverlayStyle style;
    style.line_width = 2.0f;
    const std::vector<OverlayVertex> triangles = overlay_triangles(image, style);
    ASSERT_EQ(triangles.size(), 12u);
    float lo_y = 1e9f, hi_y = -1e9f, lo_x = 1e9f, hi_x = -1e9f;
    for (std::size_t i = 6; i < 12; ++i) {  // the segment's quad
        lo_x = std::min(lo_x, triangles[i].position.x);
        hi_x = std::max(hi_x, triangles[i].position.x);
        lo_y = std::min(lo_y, triangles[i].position.y);
        hi_y = std::max(hi_y, triangles[i].position.y);
        EXPECT_EQ(triangles[i].colour, style.outline_colour);
    }
    EXPECT_FLOAT_EQ(lo_x, 9.0f);
    EXPECT_FLOAT_EQ(hi_x, 21.0f);
    EXPECT_FLOAT_EQ(lo_y, 9.0f);
    EXPECT_FLOAT_EQ(hi_y, 11.0f);
}

}  // namespace
}  // namespace caustica::ui
