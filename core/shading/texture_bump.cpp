#include "core/shading/texture_bump.h"

#include <cmath>

namespace caustica {

glm::vec3 bump_normal(const SurfaceHit& hit, const glm::vec3& normal, glm::vec2 gradient, const glm::mat2& jacobian) {
    // Work with the outward normal m; the displacement is along it whichever side is seen.
    const bool seen_from_inside = glm::dot(normal, hit.normal) < 0.0f;
    const glm::vec3 m = seen_from_inside ? -normal : normal;
    const glm::vec3 a = hit.dpdu, b = hit.dpdv;
    // c = (a x b) . m: the signed area of the (u, v) parallelogram; it may point inward.
    const float c = glm::dot(glm::cross(a, b), m);
    const float det = glm::determinant(jacobian);
    if (!(std::fabs(c) > 1e-20f) || !(std::fabs(det) > 1e-20f)) return normal;
    // Texture units to world units, and the height's gradient along the hit's own u and v.
    const float unit_size = std::sqrt(std::fabs(c) / std::fabs(det));
    const glm::vec2 h = glm::transpose(jacobian) * gradient;
    // Surface gradient of d: the dual basis of (a, b) in the tangent plane, weighted by h.
    const glm::vec3 surface_gradient = unit_size * (h.x * glm::cross(b, m) + h.y * glm::cross(m, a)) / c;
    const glm::vec3 bumped = glm::normalize(m - surface_gradient);
    if (!std::isfinite(bumped.x) || !std::isfinite(bumped.y) || !std::isfinite(bumped.z)) return normal;
    return seen_from_inside ? -bumped : bumped;
}

}  // namespace caustica
