// How the mouse and the arrow keys turn the orbit camera, GL-free so that the conventions are
// tested: the arrow keys move the camera as `caustica view --orbit YAW,PITCH` does (yaw: to the
// camera's right; pitch: up), and a left drag turns the scene with the cursor.
#pragma once

#include <glm/glm.hpp>

#include <optional>

namespace caustica::ui {

/// Degrees the camera orbits per window pixel of a left drag.
inline constexpr double orbit_degrees_per_pixel = 0.3;
/// Degrees an arrow key orbits the camera.
inline constexpr double arrow_orbit_degrees = 5.0;

/// The (yaw, pitch) degrees, in --orbit's convention (OrbitCamera::orbit), that an arrow key moves
/// the camera: Right and Left to the camera's right and left, Up and Down up and down; nullopt for
/// any other key (ui/keys.h numbers).
std::optional<glm::dvec2> arrow_orbit(int key);

/// The (yaw, pitch) degrees of a left drag by `delta` window pixels (y down): the scene follows
/// the cursor, so a drag to the right moves the camera to its left.
glm::dvec2 drag_orbit(glm::vec2 delta);

}  // namespace caustica::ui
