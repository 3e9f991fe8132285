// Rays and the surface hits they find.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
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

/// Largest |component| of a ray origin or direction Embree accepts: its ray-validity check
/// (an assertion that aborts the process) compares them with FLT_LARGE = 1.844e18.
inline constexpr float embree_coordinate_limit = 1.8e18f;

/// Whether Embree may be asked to trace the ray o + t d, t in [tnear, tfar]: components finite and
/// within embree_coordinate_limit, no NaN bound. Scenes are validated to stay far inside this
/// (scene_validate.h); the check catches what numerical accidents could still produce.
inline bool embree_traceable(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar) {
    // Written so that NaN fails a comparison.
    for (int axis = 0; axis < 3; ++axis)
        if (!(std::fabs(o[axis]) <= embree_coordinate_limit && std::fabs(d[axis]) <= embree_coordinate_limit))
            return false;
    return tnear == tnear && tfar == tfar;
}

/// embree_traceable for a Ray.
inline bool embree_traceable(const Ray& r) { return embree_traceable(r.origin, r.direction, r.tmin, r.tmax); }

/// What the integrator needs to know about the nearest surface along a ray.
struct SurfaceHit {
    float t = 0.0f;
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};  ///< unit geometric normal, outward (not flipped towards the ray)
    glm::vec2 uv{0.0f};      ///< surface parameters, for textures
    int material = -1;       ///< index into RenderScene::materials(): the surface's appearance
    /// Media on either side of the surface (material indices). `inside` is behind the normal;
    /// `outside` is in front of it, or -1 when unknown (the ray's medium stack decides).
    int medium_inside = -1;
    int medium_outside = -1;
    /// Hit on a surface of a CSG object: its medium interfaces are explicit
    /// (docs/SCENE_LANGUAGE.md, "CSG media"); otherwise classic transport colours both directions
    /// with the object's own material (docs/CAUSTICS.md, "media").
    bool in_csg = false;
    // Surface frame for textures and bump maps: object_position, uv, dpdu and dpdv are filled only
    // when the scene has a textured or bump-mapped material (they cost trigonometry per hit).
    int face = 0;                           ///< face code of analytic shapes (see SurfaceCrossing)
    int shape_kind = -1;                    ///< ShapeKind of an analytic shape, -1 for a mesh
    glm::vec3 object_position{0.0f};        ///< hit point in the primitive's object space
    glm::vec3 dpdu{0.0f}, dpdv{0.0f};       ///< the bump tangents U and V, through the normal matrix
};

}  // namespace caustica
