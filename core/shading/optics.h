// The optics formulas of the seed, written once (../shared/seed/implementation.md, section 1.3).
#pragma once

#include "core/util/radiance_range.h"

#include <glm/glm.hpp>

#include <cmath>

namespace caustica {

/// Fraction of specular light reflected at a dielectric interface (docs/SCENE_LANGUAGE.md,
/// "Materials and media"): the unpolarised average of the s and p Fresnel ratios,
///   R = 1/2 [ ((n1 cos_i - n2 cos_t) / (n1 cos_i + n2 cos_t))^2
///           + ((n2 cos_i - n1 cos_t) / (n2 cos_i + n1 cos_t))^2 ].
/// Returns 1 under total internal reflection. cos_i is the cosine of the incident angle (>= 0).
inline float fresnel_reflectance(float n1, float n2, float cos_i) {
    if (n1 == n2) return 0.0f;  // no interface at all (exactly, not up to rounding)
    cos_i = std::fmin(std::fmax(cos_i, 0.0f), 1.0f);
    const float eta = n1 / n2;
    const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    const float p = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    return 0.5f * (s * s + p * p);
}

/// Refracted direction of unit `d` through a surface with unit normal `n` facing against `d`,
/// from index n1 into n2 (Snell's law). Returns false under total internal reflection.
inline bool refract_direction(const glm::vec3& d, const glm::vec3& n, float n1, float n2, glm::vec3& out) {
    const float eta = n1 / n2;
    const float cos_i = -glm::dot(n, d);
    const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) return false;
    out = glm::normalize(eta * d + (eta * cos_i - std::sqrt(1.0f - sin2_t)) * n);
    return true;
}

/// Beer-Lambert transmittance of a coloured medium over a distance: the medium keeps the
/// fraction `colour` of each channel per unit distance, T = colour^(distance / unit_distance).
/// The colour is the material's ks (docs/SCENE_LANGUAGE.md, "medium colour"): ks = 0 lets nothing
/// through, white (and air) is clear. A colour above 1 amplifies: the result is capped at
/// max_colour_value so that it multiplies a saturated radiance without overflow (radiance_range.h).
inline glm::vec3 medium_transmittance(const glm::vec3& colour, float distance, float unit_distance) {
    if (colour == glm::vec3(1.0f)) return colour;
    if (!std::isfinite(distance)) return glm::vec3(colour.x >= 1.0f, colour.y >= 1.0f, colour.z >= 1.0f);
    const float k = distance / unit_distance;
    constexpr float cap = static_cast<float>(max_colour_value);
    return glm::min(glm::vec3(std::pow(colour.x, k), std::pow(colour.y, k), std::pow(colour.z, k)), glm::vec3(cap));
}

}  // namespace caustica
