// Bump mapping as the original renderer did it: the normal tilted along the surface tangents.
#pragma once

#include "core/geometry/ray.h"

#include <glm/glm.hpp>

namespace caustica {

/// n' = normalise(n + p_u U + p_v V) (docs/TEXTURES.md, "Bump maps"), n the outward normal, U and V
/// the hit's tangents (hit.dpdu, hit.dpdv) at unit length; a zero tangent adds nothing. `normal` is
/// unit length and may face either side: the tilt is applied to the outward normal and the result
/// faces the same side as `normal`.
glm::vec3 bump_normal(const SurfaceHit& hit, const glm::vec3& normal, glm::vec2 perturbation);

}  // namespace caustica
