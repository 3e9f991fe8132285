// The orbit camera and the image layout: exact return to the script's camera, orbits that keep
// the distance and the target, pole limits, pan that follows the cursor, zoom, retargeting.
#include "core/scene/camera.h"
#include "core/scene/orbit_camera.h"
#include "ui/camera_input.h"
#include "ui/image_layout.h"
#include "ui/keys.h"

#include <gtest/gtest.h>

#include <cmath>

namespace caustica::ui {
namespace {

CameraDesc course_camera() {
    CameraDesc c;
    c.eye = {0.0, 0.0, 7.5};
    c.view = {0.0, 0.0, -1.0};
    c.up = {0.0, 1.0, 0.0};
    c.fovy_degrees = 40.0;
    return c;
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(OrbitCamera, ArrowKeysMoveTheCameraAsOrbitDoes) {
    // `caustica view --orbit YAW,PITCH` turns the camera by OrbitCamera::orbit(YAW, PITCH): +yaw to
    // the camera's right, +pitch up. Each arrow key moves it 5 degrees that way.
    const CameraDesc script = course_camera();
    const auto moved = [&](glm::dvec2 degrees) {
        OrbitCamera orbit(script, 7.5);
        orbit.orbit(degrees.x, degrees.y);
        return orbit.eye();
    };
    ASSERT_TRUE(arrow_orbit(keys::up) && arrow_orbit(keys::down) && arrow_orbit(keys::left) && arrow_orbit(keys::right));
    expect_near(moved(*arrow_orbit(keys::up)), moved({0.0, 5.0}));     // --orbit 0,5
    expect_near(moved(*arrow_orbit(keys::down)), moved({0.0, -5.0}));  // --orbit 0,-5
    expect_near(moved(*arrow_orbit(keys::right)), moved({5.0, 0.0}));  // --orbit 5,0
    expect_near(moved(*arrow_orbit(keys::left)), moved({-5.0, 0.0}));  // --orbit -5,0
    // In words: Up raises the eye, Right moves it to the camera's right (+x here).
    EXPECT_GT(moved(*arrow_orbit(keys::up)).y, script.eye.y + 0.5);
    EXPECT_LT(moved(*arrow_orbit(keys::down)).y, script.eye.y - 0.5);
    EXPECT_GT(moved(*arrow_orbit(keys::right)).x, 0.5);
    EXPECT_LT(moved(*arrow_orbit(keys::left)).x, -0.5);
    EXPECT_FALSE(arrow_orbit(keys::a));
    // A drag turns the scene with the cursor: to the right, the camera goes to its left; up, it goes down.
    EXPECT_EQ(drag_orbit({10.0f, 0.0f}), glm::dvec2(-3.0, 0.0));
    EXPECT_EQ(drag_orbit({0.0f, -10.0f}), glm::dvec2(0.0, -3.0));
}

TEST(OrbitCamera, UnmovedCameraIsTheScriptsBitForBit) {
    CameraDesc script = course_camera();
    script.view = {0.1, -0.2, -1.0};  // not normalised: must come back as written
    const OrbitCamera orbit(script, 3.0);
    EXPECT_FALSE(orbit.moved());
    const CameraDesc d = orbit.desc();
    EXPECT_EQ(d.eye, script.eye);
    EXPECT_EQ(d.view, script.view);
    EXPECT_EQ(d.up, script.up);
    EXPECT_EQ(d.fovy_degrees, script.fovy_degrees);
    expect_near(orbit.target(), script.eye + glm::normalize(script.view) * 3.0);
}

TEST(OrbitCamera, OrbitKeepsTargetAndDistance) {
    OrbitCamera orbit(course_camera(), 7.5);
    orbit.orbit(37.0, 12.0);
    EXPECT_TRUE(orbit.moved());
    expect_near(orbit.target(), glm::dvec3(0.0));
    EXPECT_NEAR(orbit.distance(), 7.5, 1e-9);
    const CameraDesc d = orbit.desc();
    expect_near(glm::normalize(d.view), glm::normalize(orbit.target() - orbit.eye()));
}

TEST(OrbitCamera, YawMovesTheEyeToItsRightAndAFullTurnReturns) {
    OrbitCamera orbit(course_camera(), 7.5);
    orbit.orbit(90.0, 0.0);
    expect_near(orbit.eye(), glm::dvec3(7.5, 0.0, 0.0), 1e-9);  // the camera's right was +x
    orbit.orbit(270.0, 0.0);
    expect_near(orbit.eye(), glm::dvec3(0.0, 0.0, 7.5), 1e-9);
}

TEST(OrbitCamera, PitchGoesUpAndStopsShortOfThePole) {
    OrbitCamera orbit(course_camera(), 7.5);
    orbit.orbit(0.0, 30.0);
    EXPECT_NEAR(orbit.eye().y, 7.5 * std::sin(glm::radians(30.0)), 1e-9);
    orbit.orbit(0.0, 500.0);
    const double polar = std::acos(orbit.eye().y / 7.5);
    EXPECT_NEAR(glm::degrees(polar), 1.0, 1e-6);  // clamped one degree from straight above
    // The camera stays usable: the view is not parallel to up.
    const Camera camera(orbit.desc(), 64, 64);
    glm::vec2 pixel;
    ASSERT_TRUE(camera.project(glm::vec3(0.0f), pixel));
    EXPECT_NEAR(pixel.x, 32.0f, 1e-3f);
    EXPECT_NEAR(pixel.y, 32.0f, 1e-3f);
}

TEST(OrbitCamera, PanFollowsTheCursorAtTheTarget) {
    OrbitCamera orbit(course_camera(), 7.5);
    const int height = 400;
    // A point at the target sits at the image centre; after panning by (dx, dy) pixels it sits
    // (dx, dy) pixels away from the centre, as under a dragged cursor.
    orbit.pan_pixels({25.0, -10.0}, height, height);
    const Camera camera(orbit.desc(), height, height);
    glm::vec2 pixel;
    ASSERT_TRUE(camera.project(glm::vec3(0.0f), pixel));
    EXPECT_NEAR(pixel.x, 200.0f + 25.0f, 1e-3f);
    EXPECT_NEAR(pixel.y, 200.0f - 10.0f, 1e-3f);
    EXPECT_NEAR(orbit.distance(), 7.5, 1e-9);
}

TEST(OrbitCamera, ZoomScalesTheDistanceOnly) {
    OrbitCamera orbit(course_camera(), 7.5);
    orbit.zoom(0.5);
    expect_near(orbit.target(), glm::dvec3(0.0));
    expect_near(orbit.eye(), glm::dvec3(0.0, 0.0, 3.75));
    orbit.zoom(0.0);  // ignored
    expect_near(orbit.eye(), glm::dvec3(0.0, 0.0, 3.75));
}

TEST(OrbitCamera, SetTargetKeepsTheEyeAndRefusesThePole) {
    OrbitCamera orbit(course_camera(), 7.5);
    orbit.set_target({1.0, -1.0, 0.0});
    expect_near(orbit.eye(), glm::dvec3(0.0, 0.0, 7.5));
    expect_near(orbit.target(), glm::dvec3(1.0, -1.0, 0.0));
    orbit.set_target({0.0, 100.0, 7.5});  // straight above the eye
    expect_near(orbit.target(), glm::dvec3(1.0, -1.0, 0.0));
}

TEST(OrbitCamera, SetTargetDistanceKeepsTheView) {
    OrbitCamera orbit(course_camera(), 1.0);
    orbit.set_target_distance(9.5);
    EXPECT_FALSE(orbit.moved());
    expect_near(orbit.target(), glm::dvec3(0.0, 0.0, -2.0));
}

TEST(OrbitCamera, DefaultTargetIsWhereTheViewPassesTheOrigin) {
    EXPECT_DOUBLE_EQ(default_target_distance(course_camera()), 7.5);
    CameraDesc away = course_camera();
    away.view = {0.0, 0.0, 1.0};
    EXPECT_DOUBLE_EQ(default_target_distance(away), 1.0);
}

TEST(ImageLayout, SmallImagesAreMagnifiedByWholeFactorsAndCentred) {
    const ImageLayout a = fit_image({0.0f, 0.0f}, {910.0f, 720.0f}, 256, 192);
    EXPECT_EQ(a.scale, 3.0f);
    EXPECT_EQ(a.origin, glm::vec2(71.0f, 72.0f));
    const ImageLayout b = fit_image({0.0f, 0.0f}, {910.0f, 720.0f}, 512, 512);
    EXPECT_EQ(b.scale, 1.0f);
    EXPECT_EQ(b.to_image(b.to_window({10.5f, 20.5f})), glm::vec2(10.5f, 20.5f));
    const ImageLayout c = fit_image({0.0f, 0.0f}, {910.0f, 720.0f}, 1280, 720);
    EXPECT_NEAR(c.scale, 910.0f / 1280.0f, 1e-6f);
    EXPECT_TRUE(c.contains({455.0f, 360.0f}));
    EXPECT_FALSE(c.contains({455.0f, 10.0f}));
}

}  // namespace
}  // namespace caustica::ui
