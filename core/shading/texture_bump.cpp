#include "core/shading/texture_bump.h"

#include <cmath>

namespace caustica {
namespace {

/// `v` at unit length, or zero when it has no direction.
glm::vec3 unit_or_zero(const glm::vec3& v) {
    const float length = glm::length(v);
    return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f);
}

}  // namespace

glm::vec3 bump_normal(const SurfaceHit& hit, const glm::vec3& normal, glm::vec2 perturbation) {
    const bool seen_from_inside = glm::dot(normal, hit.normal) < 0.0f;
    const glm::vec3 outward = seen_from_inside ? -normal : normal;
    const glm::vec3 tilted =
        outward + perturbation.x * unit_or_zero(hit.dpdu) + perturbation.y * unit_or_zero(hit.dpdv);
    const float length = glm::length(tilted);
    if (!(length > 0.0f) || !std::isfinite(length)) return normal;
    const glm::vec3 bumped = tilted / length;
    return seen_from_inside ? -bumped : bumped;
}

}  // namespace caustica
