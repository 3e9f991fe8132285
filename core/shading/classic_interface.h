// How the classic integrator sees a surface between two regions, for its view rays and its
// photons alike (docs/CAUSTICS.md, "The material entered"). The original renderer knew the object
// it hit and the interfaces a CSG union records, nothing else (no stack of nested media):
// - the refractive indices on the two sides come from the CSG interface, or, for an object that is
//   not part of a CSG, from the object inside and air outside;
// - every multiplier, odds and store at the surface uses the material *entered*: the region on the
//   far side along the ray in a CSG (its outside is air), the object itself in both directions
//   otherwise, and an opaque surface's own material.
// Air (the outside, or gr.air()) behaves as a material with kd = 0, ks = 1 and index 1.
#pragma once

#include "core/geometry/ray.h"
#include "core/shading/material.h"

#include <glm/glm.hpp>

#include <vector>

namespace caustica {

/// The regions on both sides of a surface along a ray, as material indices (-1: the outside).
struct ClassicInterface {
    bool entering = false;  ///< the ray crosses against the outward normal
    int near_side = -1;     ///< region the ray arrives from (for the index n1)
    int far_side = -1;      ///< region behind the surface (for the index n2)
    int entered = -1;       ///< material whose kd, ks and flags rule the surface (-1: air)
};

inline ClassicInterface classic_interface(const std::vector<Material>& materials, const SurfaceHit& hit,
                                          const glm::vec3& direction) {
    ClassicInterface side;
    side.entering = glm::dot(hit.normal, direction) < 0.0f;
    const int inside = hit.in_csg ? hit.medium_inside : hit.material;
    const int outside = hit.in_csg ? hit.medium_outside : -1;
    side.near_side = side.entering ? outside : inside;
    side.far_side = side.entering ? inside : outside;
    const bool own = !hit.in_csg || !materials[static_cast<std::size_t>(hit.material)].transparent;
    side.entered = own ? hit.material : side.far_side;
    return side;
}

/// The refractive index of a region (-1: the outside, index 1).
inline float classic_index(const std::vector<Material>& materials, int region) {
    return region < 0 ? 1.0f : materials[static_cast<std::size_t>(region)].refractive_index;
}

/// Whether a region is empty: the outside or gr.air() (kd = 0, ks = 1, index 1).
inline bool classic_is_air(const std::vector<Material>& materials, int region) {
    return region < 0 || materials[static_cast<std::size_t>(region)].air;
}

/// The ks of a region: 1 for air, else its material's.
inline glm::vec3 classic_ks(const std::vector<Material>& materials, int region) {
    return classic_is_air(materials, region) ? glm::vec3(1.0f) : materials[static_cast<std::size_t>(region)].ks;
}

}  // namespace caustica
