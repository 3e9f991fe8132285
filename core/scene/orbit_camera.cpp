#include "core/scene/orbit_camera.h"

#include "core/scene/camera.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

constexpr double min_pole_angle = glm::radians(1.0);

glm::dvec3 rotate_about(const glm::dvec3& v, const glm::dvec3& axis, double radians) {
    return glm::angleAxis(radians, glm::normalize(axis)) * v;
}

}  // namespace

OrbitCamera::OrbitCamera(const CameraDesc& script, double target_distance)
    : script_(script), eye_(script.eye), up_(glm::normalize(script.up)) {
    const double d = target_distance > 0.0 && std::isfinite(target_distance) ? target_distance : 1.0;
    target_ = eye_ + glm::normalize(script.view) * d;
}

void OrbitCamera::orbit(double yaw_degrees, double pitch_degrees) {
    if (yaw_degrees == 0.0 && pitch_degrees == 0.0) return;
    glm::dvec3 offset = eye_ - target_;
    offset = rotate_about(offset, up_, glm::radians(yaw_degrees));
    // Pitch about the camera's right axis, keeping the eye off the poles of the up axis.
    const double length = glm::length(offset);
    const double polar = std::acos(std::clamp(glm::dot(offset / length, up_), -1.0, 1.0));
    const double wanted = std::clamp(polar - glm::radians(pitch_degrees), min_pole_angle, glm::pi<double>() - min_pole_angle);
    const glm::dvec3 right = glm::cross(-offset, up_);
    if (glm::length(right) > 1e-12 * length) offset = rotate_about(offset, right, wanted - polar);
    eye_ = target_ + offset;
    moved_ = true;
}

void OrbitCamera::zoom(double factor) {
    if (!(factor > 0.0) || factor == 1.0) return;
    const glm::dvec3 offset = eye_ - target_;
    const double length = glm::length(offset);
    const double wanted = std::max(length * factor, 1e-6 * std::max(1.0, glm::length(target_)));
    eye_ = target_ + offset * (wanted / length);
    moved_ = true;
}

void OrbitCamera::pan_pixels(glm::dvec2 pixels, int image_width, int image_height) {
    if (image_width <= 0 || image_height <= 0 || (pixels.x == 0.0 && pixels.y == 0.0)) return;
    const glm::dvec3 forward = glm::normalize(target_ - eye_);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
    const glm::dvec3 up = glm::cross(right, forward);
    const double per_pixel = 2.0 * distance() * std::tan(glm::radians(vertical_fov_degrees(script_, image_width, image_height)) * 0.5) /
                             image_height;  // gr.render's angle is the horizontal one
    const glm::dvec3 delta = (-pixels.x * right + pixels.y * up) * per_pixel;
    eye_ += delta;
    target_ += delta;
    moved_ = true;
}

void OrbitCamera::set_target(const glm::dvec3& target) {
    const glm::dvec3 offset = target - eye_;
    const double length = glm::length(offset);
    if (!(length > 0.0) || !std::isfinite(length)) return;
    // Refuse targets straight above or below the eye: the view would be parallel to up.
    if (std::abs(glm::dot(offset / length, up_)) > std::cos(min_pole_angle)) return;
    target_ = target;
    moved_ = true;
}

void OrbitCamera::set_target_distance(double distance) {
    if (!(distance > 0.0) || !std::isfinite(distance)) return;
    target_ = eye_ + glm::normalize(target_ - eye_) * distance;  // the view does not change
}

CameraDesc OrbitCamera::desc() const {
    if (!moved_) return script_;
    CameraDesc d = script_;
    d.eye = eye_;
    d.view = glm::normalize(target_ - eye_);
    d.up = up_;
    return d;
}

double default_target_distance(const CameraDesc& camera) {
    const glm::dvec3 view = glm::normalize(camera.view);
    const double along = glm::dot(-camera.eye, view);
    return along > 0.0 ? along : 1.0;
}

}  // namespace caustica
