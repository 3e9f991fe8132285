// Rays and the surface hits they find.
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace caustica {

inline constexpr float ray_infinity = std::numeric_limits<float>::infinity();

/// A ray segment o + t d for t in [tmin, tmax]; d is unit length for rays the integrator makes.
struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    float tmin = 0.0f;
    float tmax = ray_infinity;
};

/// What the integrator needs to know about the nearest surface along a ray.
struct SurfaceHit {
    float t = 0.0f;
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};  ///< unit geometric normal, outward (not flipped towards the ray)
    glm::vec2 uv{0.0f};      ///< surface parameters, for textures
    int material = -1;       ///< index into RenderScene::materials()
    int face = 0;            ///< face code of analytic shapes (see SurfaceCrossing)
};

}  // namespace caustica
