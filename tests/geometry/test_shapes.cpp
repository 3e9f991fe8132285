// Analytic primitives against closed-form answers, including rays from inside and grazing rays.
#include "core/geometry/shapes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace caustica;

namespace {

const Shape unit_sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
const Shape cylinder{ShapeKind::cylinder, glm::vec3(0.0f), glm::vec3(1.0f)};
const Shape cone{ShapeKind::cone, glm::vec3(0.0f), glm::vec3(1.0f)};

void expect_vec_near(glm::vec3 a, glm::vec3 b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(Sphere, HeadOnHitHasEntryAndExit) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(unit_sphere, {0, 0, 5}, {0, 0, -1}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, 4.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 6.0f);
    expect_vec_near(glm::normalize(iv.entry.normal), {0, 0, 1}, 1e-6f);
    expect_vec_near(glm::normalize(iv.exit.normal), {0, 0, -1}, 1e-6f);
}

TEST(Sphere, UnnormalisedDirectionScalesT) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(unit_sphere, {0, 0, 5}, {0, 0, -2}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, 2.0f);
}

TEST(Sphere, RayFromInsideStartsBehind) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(unit_sphere, {0, 0, 0}, {1, 0, 0}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, -1.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 1.0f);
}

TEST(Sphere, OffsetCentreAndRadius) {
    const Shape s{ShapeKind::sphere, glm::vec3(200, 50, -100), glm::vec3(150)};
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(s, {200, 50, 800}, {0, 0, -1}, iv));
    EXPECT_NEAR(iv.entry.t, 750.0f, 1e-3f);
    EXPECT_NEAR(iv.exit.t, 1050.0f, 1e-3f);
}

TEST(Sphere, GrazingRayTouchesOnceAndAMissJustOutside) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(unit_sphere, {-5, 1, 0}, {1, 0, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 5.0f, 1e-3f);
    EXPECT_NEAR(iv.exit.t, 5.0f, 1e-3f);
    EXPECT_FALSE(intersect_shape_interval(unit_sphere, {-5, 1.0001f, 0}, {1, 0, 0}, iv));
}

TEST(Sphere, FarAwayRayKeepsItsPrecision) {
    // bh^2 - ac would lose every digit here; the projected form keeps the chord length.
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(unit_sphere, {0, 0.6f, 1e5f}, {0, 0, -1}, iv));
    EXPECT_NEAR(iv.exit.t - iv.entry.t, 1.6f, 0.02f);
}

TEST(Box, SlabsGiveFaces) {
    const Shape box{ShapeKind::box, glm::vec3(-1), glm::vec3(1)};
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(box, {-3, 0.5f, 0.2f}, {1, 0, 0}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, 2.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 4.0f);
    EXPECT_EQ(iv.entry.face, 0);
    EXPECT_EQ(iv.exit.face, 1);
    expect_vec_near(iv.entry.normal, {-1, 0, 0}, 0);
    expect_vec_near(iv.exit.normal, {1, 0, 0}, 0);
    ASSERT_TRUE(intersect_shape_interval(box, {0.3f, 0.3f, 0.3f}, {0, -1, 0}, iv));  // from inside
    EXPECT_FLOAT_EQ(iv.entry.t, -0.7f);
    EXPECT_FLOAT_EQ(iv.exit.t, 1.3f);
    EXPECT_EQ(iv.exit.face, 2);
    EXPECT_FALSE(intersect_shape_interval(box, {-3, 1.5f, 0}, {1, 0, 0}, iv));
}

TEST(Box, ParallelRayOnAFacePlaneIsHandled) {
    const Shape box{ShapeKind::box, glm::vec3(0), glm::vec3(1)};
    ShapeInterval iv;
    // Lies in the plane y = 1 (a face), travelling along x: 0 * inf must not poison the answer.
    ASSERT_TRUE(intersect_shape_interval(box, {-1, 1, 0.5f}, {1, 0, 0}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, 1.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 2.0f);
}

TEST(Cylinder, SideAndCaps) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(cylinder, {-5, 0, 0}, {1, 0, 0}, iv));
    EXPECT_FLOAT_EQ(iv.entry.t, 4.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 6.0f);
    EXPECT_EQ(iv.entry.face, 0);
    ASSERT_TRUE(intersect_shape_interval(cylinder, {0.5f, 5, 0}, {0, -1, 0}, iv));  // down the axis
    EXPECT_FLOAT_EQ(iv.entry.t, 4.0f);
    EXPECT_FLOAT_EQ(iv.exit.t, 6.0f);
    EXPECT_EQ(iv.entry.face, 1);  // top cap
    EXPECT_EQ(iv.exit.face, 2);   // bottom cap
    expect_vec_near(iv.entry.normal, {0, 1, 0}, 0);
    EXPECT_FALSE(intersect_shape_interval(cylinder, {1.5f, 5, 0}, {0, -1, 0}, iv));  // parallel, outside
    EXPECT_FALSE(intersect_shape_interval(cylinder, {-5, 1.5f, 0}, {1, 0, 0}, iv));  // above
    // Diagonal: enters the side at y = 0.5, leaves through the top cap at x = -0.5.
    ASSERT_TRUE(intersect_shape_interval(cylinder, {-2, -0.5f, 0}, glm::normalize(glm::vec3(1, 1, 0)), iv));
    EXPECT_NEAR(iv.entry.t, std::sqrt(2.0f), 1e-5f);
    EXPECT_EQ(iv.entry.face, 0);
    EXPECT_NEAR(iv.exit.t, 1.5f * std::sqrt(2.0f), 1e-5f);
    EXPECT_EQ(iv.exit.face, 1);
}

TEST(Cone, ApexUpBaseDown) {
    // Height 1 (docs/SCENE_LANGUAGE.md, "cone"): apex at y = 1/2, base radius 1 at y = -1/2,
    // radius 1/2 - y.
    ShapeInterval iv;
    // Horizontal through y = 0: radius 1/2 - 0 = 0.5.
    ASSERT_TRUE(intersect_shape_interval(cone, {-5, 0, 0}, {1, 0, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 4.5f, 1e-5f);
    EXPECT_NEAR(iv.exit.t, 5.5f, 1e-5f);
    const glm::vec3 n = glm::normalize(iv.entry.normal);
    expect_vec_near(n, glm::normalize(glm::vec3(-1, 1, 0)), 1e-5f);  // outward and upward, 45 degrees
    // Down the axis: in at the apex (y = 1/2), out through the base (y = -1/2).
    ASSERT_TRUE(intersect_shape_interval(cone, {0, 5, 0}, {0, -1, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 4.5f, 1e-4f);
    EXPECT_NEAR(iv.exit.t, 5.5f, 1e-5f);
    EXPECT_EQ(iv.exit.face, 2);
    // Up from below at x = 0.9: through the base, out where the radius is 0.9 (y = -0.4).
    ASSERT_TRUE(intersect_shape_interval(cone, {0.9f, -5, 0}, {0, 1, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 4.5f, 1e-5f);
    EXPECT_EQ(iv.entry.face, 2);
    EXPECT_NEAR(iv.exit.t, 4.6f, 1e-4f);
    // The upper nappe of the double cone is not part of the solid.
    EXPECT_FALSE(intersect_shape_interval(cone, {-5, 1, 0}, {1, 0, 0}, iv));
    EXPECT_FALSE(intersect_shape_interval(cone, {-5, 0.75f, 0}, {1, 0, 0}, iv));
}

TEST(Cone, RayFromInsideExitsThroughTheSide) {
    ShapeInterval iv;
    ASSERT_TRUE(intersect_shape_interval(cone, {0, -0.25f, 0}, {1, 0, 0}, iv));  // radius 0.75 there
    EXPECT_LT(iv.entry.t, 0.0f);
    EXPECT_NEAR(iv.exit.t, 0.75f, 1e-5f);
}

TEST(ShapeUv, ParametersStayInTheUnitSquare) {
    for (float a = 0.0f; a < 6.3f; a += 0.3f) {
        const glm::vec3 p(std::cos(a), std::sin(a) * 0.5f, std::sin(a));
        for (const Shape& s : {unit_sphere, cylinder, cone}) {
            const glm::vec2 uv = shape_uv(s, glm::normalize(p), 0);
            EXPECT_GE(uv.x, 0.0f);
            EXPECT_LE(uv.x, 1.0f);
            EXPECT_GE(uv.y, 0.0f);
            EXPECT_LE(uv.y, 1.0f);
        }
    }
    // v = (1 + y) / 2 (docs/TEXTURES.md): the north pole is the image's top row, v = 1.
    EXPECT_NEAR(shape_uv(unit_sphere, {0, 1, 0}, 0).y, 1.0f, 1e-6f);
    EXPECT_NEAR(shape_uv(unit_sphere, {0, -1, 0}, 0).y, 0.0f, 1e-6f);
}
