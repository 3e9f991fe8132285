#include "core/shading/texture_procedural.h"

#include <cmath>

namespace caustica {
namespace {

constexpr double pi = 3.14159265358979323846;

}  // namespace

std::optional<glm::vec3> checker_colour(const std::string& name) {
    if (name == "redcheck") return glm::vec3(1.0f, 0.0f, 0.0f);
    if (name == "greencheck") return glm::vec3(0.0f, 1.0f, 0.0f);
    if (name == "bluecheck") return glm::vec3(0.0f, 0.8f, 1.0f);
    if (name == "whitecheck") return glm::vec3(1.0f);
    return std::nullopt;
}

glm::vec3 checker(const glm::vec3& colour, glm::vec2 uv) {
    const double i = std::floor(static_cast<double>(uv.x) * checks_per_unit);
    const double j = std::floor(static_cast<double>(uv.y) * checks_per_unit);
    const bool odd = std::fabs(std::fmod(i + j, 2.0)) == 1.0;
    return odd ? colour : glm::vec3(0.0f);
}

glm::vec2 ripple_perturbation(glm::vec2 uv) {
    const glm::dvec2 offset = glm::dvec2(uv) - glm::dvec2(0.5);
    const double rho = glm::length(offset);
    if (!(rho > 0.0)) return glm::vec2(0.0f);
    return glm::vec2(std::cos(2.0 * pi * ripples_per_unit * rho) / rho * offset);
}

}  // namespace caustica
