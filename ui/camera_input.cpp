#include "ui/camera_input.h"

#include "ui/keys.h"

namespace caustica::ui {

std::optional<glm::dvec2> arrow_orbit(int key) {
    switch (key) {
    case keys::right: return glm::dvec2(arrow_orbit_degrees, 0.0);
    case keys::left: return glm::dvec2(-arrow_orbit_degrees, 0.0);
    case keys::up: return glm::dvec2(0.0, arrow_orbit_degrees);
    case keys::down: return glm::dvec2(0.0, -arrow_orbit_degrees);
    default: return std::nullopt;
    }
}

glm::dvec2 drag_orbit(glm::vec2 delta) {
    return glm::dvec2(-delta.x * orbit_degrees_per_pixel, delta.y * orbit_degrees_per_pixel);
}

}  // namespace caustica::ui
