// The range of values shading computes with, chosen so that float arithmetic cannot overflow
// (docs/RELIABILITY.md, "No NaN or infinity from finite input").
//
// Inputs: every colour-like value (kd, ks, light colour, ambient, miss colour, medium
// transmittance) is at most max_colour_value; scene_validate refuses larger ones with the script
// line. Results: every radiance, photon power and path weight is saturated at max_radiance, and
// light attenuation at max_attenuation. Then no product of a saturated result and an input, nor
// the sum of a few of them, exceeds about 1e37 < FLT_MAX (3.4e38): no infinity appears, and so no
// NaN from 0 x inf or inf - inf either. Displays clip at 1, so saturating at 1e30 never shows.
#pragma once

#include <glm/glm.hpp>

namespace caustica {

/// Largest colour component accepted from a scene: a million times white.
inline constexpr double max_colour_value = 1e6;

/// Largest radiance (and photon power, and path weight) the shading keeps.
inline constexpr float max_radiance = 1e30f;

/// Largest light attenuation 1 / (c0 + c1 d + c2 d^2): reached only a hair from a light without
/// a constant term. With a light colour and a Phong term of at most 1e6 and 2e6, one light adds at
/// most 2e30 before saturation.
inline constexpr float max_attenuation = 1e18f;

/// Caps a non-negative value at max_radiance (infinity becomes max_radiance). NaN passes through:
/// it is a bug to find, not a value to hide.
inline float saturate(float x) { return x > max_radiance ? max_radiance : x; }

/// saturate per component.
inline glm::vec3 saturate(const glm::vec3& v) { return {saturate(v.x), saturate(v.y), saturate(v.z)}; }

/// Caps a value of either sign at +-max_radiance: the classic integrator's terms carry n.v
/// unflipped (docs/CAUSTICS.md, "normals", "estimate") and go negative on surfaces seen from behind.
inline float saturate_signed(float x) { return x < -max_radiance ? -max_radiance : saturate(x); }

/// saturate_signed per component.
inline glm::vec3 saturate_signed(const glm::vec3& v) {
    return {saturate_signed(v.x), saturate_signed(v.y), saturate_signed(v.z)};
}

}  // namespace caustica
