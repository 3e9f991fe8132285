// The procedural textures (checkerboards) and bump map (sine ripples) that scenes name.
// Their exact definitions are in docs/TEXTURES.md.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace caustica {

/// Checks along each texture axis: 8 x 8 squares over uv in [0,1]^2 (the pattern repeats beyond).
inline constexpr int checks_per_unit = 8;

/// Ripple crests per unit of distance from the texture's centre (0.5, 0.5).
inline constexpr int ripples_per_unit = 8;

/// The colour of a named checkerboard ("redcheck" -> red, ...), or nothing for another name.
std::optional<glm::vec3> checker_colour(const std::string& name);

/// Checkerboard at uv: `colour` on the square that holds (0, 0) and every other square, black on the rest.
glm::vec3 checker(const glm::vec3& colour, glm::vec2 uv);

/// Height of the concentric ripples at uv, in texture units: a cos(2 pi k r), r = |uv - (0.5, 0.5)|,
/// with k = ripples_per_unit and a chosen so that the steepest slope is 1/2.
float ripple_height(glm::vec2 uv);

/// Analytic gradient (dh/du, dh/dv) of ripple_height; zero at the centre, on crests and in troughs.
glm::vec2 ripple_gradient(glm::vec2 uv);

}  // namespace caustica
