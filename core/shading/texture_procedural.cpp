#include "core/shading/texture_procedural.h"

#include <cmath>

namespace caustica {
namespace {

constexpr float two_pi = 6.28318530717958647692f;
/// Ripple amplitude: the slope a 2 pi k peaks at 1/2 (a tilt of atan(1/2), about 26.6 degrees).
constexpr float ripple_amplitude = 0.5f / (two_pi * static_cast<float>(ripples_per_unit));

}  // namespace

std::optional<glm::vec3> checker_colour(const std::string& name) {
    if (name == "redcheck") return glm::vec3(1.0f, 0.0f, 0.0f);
    if (name == "greencheck") return glm::vec3(0.0f, 1.0f, 0.0f);
    if (name == "bluecheck") return glm::vec3(0.0f, 0.0f, 1.0f);
    if (name == "whitecheck") return glm::vec3(1.0f);
    return std::nullopt;
}

glm::vec3 checker(const glm::vec3& colour, glm::vec2 uv) {
    const double i = std::floor(static_cast<double>(uv.x) * checks_per_unit);
    const double j = std::floor(static_cast<double>(uv.y) * checks_per_unit);
    const bool odd = std::fmod(std::fabs(i + j), 2.0) == 1.0;
    return odd ? glm::vec3(0.0f) : colour;
}

float ripple_height(glm::vec2 uv) {
    const float r = glm::length(uv - glm::vec2(0.5f));
    return ripple_amplitude * std::cos(two_pi * ripples_per_unit * r);
}

glm::vec2 ripple_gradient(glm::vec2 uv) {
    const glm::vec2 offset = uv - glm::vec2(0.5f);
    const float r = glm::length(offset);
    if (r == 0.0f) return glm::vec2(0.0f);
    const float k = two_pi * ripples_per_unit;
    return (-ripple_amplitude * k * std::sin(k * r) / r) * offset;
}

}  // namespace caustica
