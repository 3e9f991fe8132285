// Bump mapping: the shading normal of a surface displaced along its normal by a height field.
#pragma once

#include "core/geometry/ray.h"

#include <glm/glm.hpp>

namespace caustica {

/// Blinn's bump mapping. The surface is displaced outward by d = L * H, where H is the height
/// field in texture units and L = sqrt(|dp/du' x dp/dv'|) is the local size of one unit of
/// texture space (u', v' = the texture coordinates), so bumps keep their shape when the object
/// is scaled. `gradient` is (dH/du', dH/dv'); `jacobian` is d(u',v')/d(hit.uv) (TextureLookup).
/// The result is n' = normalize(n - grad_s d), grad_s the surface gradient built from hit.dpdu
/// and hit.dpdv; it faces the same side as `normal`. A singular frame (zero tangents or
/// Jacobian) leaves `normal` unchanged.
glm::vec3 bump_normal(const SurfaceHit& hit, const glm::vec3& normal, glm::vec2 gradient, const glm::mat2& jacobian);

}  // namespace caustica
