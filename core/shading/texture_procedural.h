// The procedural textures (checkerboards) and bump map (sine ripples) that scenes name.
// Their exact definitions are in docs/TEXTURES.md ("Procedural textures", "Bump maps").
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace caustica {

/// Checker squares per unit of u and of v.
inline constexpr int checks_per_unit = 24;

/// Ripple crests per unit of distance from the texture's centre (0.5, 0.5).
inline constexpr int ripples_per_unit = 15;

/// The colour of a named checkerboard: redcheck (1,0,0), greencheck (0,1,0), bluecheck
/// (0, 0.8, 1), whitecheck (1,1,1); nothing for another name.
std::optional<glm::vec3> checker_colour(const std::string& name);

/// Checkerboard at uv: n = floor(24 u) + floor(24 v); `colour` where n is odd, black where it is
/// even (the square at (0, 0) is black).
glm::vec3 checker(const glm::vec3& colour, glm::vec2 uv);

/// The ripple bump map's perturbation p = cos(30 pi rho) r_hat at uv, rho = |uv - (1/2, 1/2)|,
/// r_hat its direction (zero at the centre): the normal becomes normalise(n + p_u U + p_v V).
glm::vec2 ripple_perturbation(glm::vec2 uv);

}  // namespace caustica
