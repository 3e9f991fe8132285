#include "core/scene/camera.h"

#include <cmath>

namespace caustica {

namespace {

/// The widest vertical angle the image plane is given, in degrees.
constexpr double max_vertical_fov_degrees = 179.0;

/// `v` at unit length, scaled down first so that a huge or tiny vector normalises exactly.
glm::dvec3 unit(const glm::dvec3& v) {
    const double m = std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
    return m > 0.0 ? glm::normalize(v / m) : v;
}

}  // namespace

double vertical_fov_degrees(const CameraDesc& desc, int width, int height) {
    return desc.fovy_degrees * static_cast<double>(height) / static_cast<double>(width);
}

Camera::Camera(const CameraDesc& desc, int width, int height) : width_(width), height_(height) {
    const glm::dvec3 forward = unit(desc.view);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, unit(desc.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    eye_ = glm::vec3(desc.eye);
    forward_ = glm::vec3(forward);
    right_ = glm::vec3(right);
    up_ = glm::vec3(up);
    // Up only fixes the roll: the image plane stays perpendicular to the view direction.
    // A tall image can push fov_x / aspect to 180 degrees or more, where the plane has no extent:
    // keep it just below (the original's image there is meaningless; ours stays upright).
    const double vertical = std::fmin(vertical_fov_degrees(desc, width, height), max_vertical_fov_degrees);
    const double half_height = std::tan(glm::radians(vertical) * 0.5);
    half_height_ = static_cast<float>(half_height);
    half_width_ = static_cast<float>(half_height * width / height);
}

Ray Camera::generate(float x, float y) const {
    const float sx = (2.0f * x / static_cast<float>(width_) - 1.0f) * half_width_;
    const float sy = (1.0f - 2.0f * y / static_cast<float>(height_)) * half_height_;
    return Ray{eye_, glm::normalize(forward_ + sx * right_ + sy * up_), 0.0f, ray_infinity};
}

bool Camera::project(const glm::vec3& world, glm::vec2& pixel) const {
    const glm::vec3 v = world - eye_;
    const float depth = glm::dot(v, forward_);
    if (depth <= 0.0f) return false;
    const float sx = glm::dot(v, right_) / depth / half_width_;
    const float sy = glm::dot(v, up_) / depth / half_height_;
    pixel = {0.5f * (sx + 1.0f) * static_cast<float>(width_), 0.5f * (1.0f - sy) * static_cast<float>(height_)};
    return true;
}

}  // namespace caustica
