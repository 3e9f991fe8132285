// Materials as the renderer uses them (resolved from MaterialDesc).
#pragma once

#include "core/util/radiance_range.h"
#include "core/scene/scene_desc.h"

#include <glm/glm.hpp>

namespace caustica {

/// The course's Phong material with the original's mirror and dielectric extensions.
struct Material {
    glm::vec3 kd{0.0f}, ks{0.0f};
    float shininess = 0.0f;
    bool reflective = false;       ///< mirror weighted by ks
    bool transparent = false;      ///< dielectric (set_ri) or air: Fresnel split of ks
    float refractive_index = 1.0f;
    bool air = false;              ///< gr.air(): an empty medium, index 1, no surface of its own
    /// Colour of a transparent material's medium per unit distance: its ks; air and opaque: 1
    /// (docs/SCENE_LANGUAGE.md, "medium colour").
    glm::vec3 medium_colour{1.0f};

    /// Converts the scene description's material.
    static Material from_desc(const MaterialDesc& desc) {
        Material m;
        m.kd = glm::vec3(desc.kd);
        m.ks = glm::vec3(desc.ks);
        m.shininess = static_cast<float>(desc.shininess);
        m.reflective = desc.reflective;
        m.air = desc.air;
        m.transparent = desc.refractive_index.has_value() || desc.air;
        m.refractive_index = desc.air ? 1.0f : static_cast<float>(desc.refractive_index.value_or(1.0));
        m.medium_colour = m.transparent && !m.air ? m.ks : glm::vec3(1.0f);
        return m;
    }
};

/// A point light (radius 0) or spherical light.
struct Light {
    glm::vec3 position{0.0f}, colour{0.0f}, falloff{1.0f, 0.0f, 0.0f};
    float radius = 0.0f;

    /// The course's attenuation: 1 / (c0 + c1 d + c2 d^2), at most max_attenuation (a point a hair
    /// from a light without constant term, or a denominator that underflows to 0).
    float attenuation(float distance) const {
        const float denominator = falloff.x + falloff.y * distance + falloff.z * distance * distance;
        return denominator > 1.0f / max_attenuation ? 1.0f / denominator : max_attenuation;
    }
};

}  // namespace caustica
