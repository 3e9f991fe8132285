// Analytic primitives in their own object space. Every shape is convex, so a ray crosses it in
// at most one interval [entry, exit]; nearest-hit queries and (later) CSG both build on that.
#pragma once

#include <glm/glm.hpp>

namespace caustica {

/// The analytic shape kinds, after the scene's convention has been resolved.
enum class ShapeKind : unsigned char {
    sphere,    ///< centre + radius
    box,       ///< axis-aligned [lo, hi]
    cylinder,  ///< axis y, y in [-1,1], radius 1, capped
    cone,      ///< axis y, height 1: apex at y = +1/2, radius 1 at the base y = -1/2, base capped
};

/// An analytic shape with its parameters (only sphere and box use them).
struct Shape {
    ShapeKind kind = ShapeKind::sphere;
    glm::vec3 a{0.0f};   ///< sphere centre, or box lower corner
    glm::vec3 b{1.0f};   ///< (radius, -, -) for a sphere, or box upper corner
};

/// One crossing of a shape's surface: ray parameter, outward object-space normal (not unit),
/// surface parameters, and which face (for texture remaps: 0 = side, 1 = top cap, 2 = bottom cap;
/// boxes: 0..5 = -x,+x,-y,+y,-z,+z).
struct SurfaceCrossing {
    float t = 0.0f;
    glm::vec3 normal{0.0f};
    int face = 0;
};

/// The ray's interval inside a shape: entry and exit crossings. Valid when entry.t <= exit.t.
struct ShapeInterval {
    SurfaceCrossing entry, exit;
};

/// Computes where the line o + t d (d need not be unit) is inside `shape`.
/// Returns false when it misses. The interval may start at negative t (ray origin inside).
bool intersect_shape_interval(const Shape& shape, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out);

/// Object-space bounding box of a shape.
void shape_bounds(const Shape& shape, glm::vec3& lo, glm::vec3& hi);

/// Texture coordinates (u, v in [0,1], v = 1 at an image's top row) of an object-space point on
/// `face` of the shape: the original renderer's layouts (docs/TEXTURES.md).
glm::vec2 shape_uv(const Shape& shape, const glm::vec3& p, int face);

/// The bump-map tangents U and V at a surface point, in object space, unit length (or zero where
/// the original has none, e.g. the sphere's U at (0, 0, +-1) or the cone's apex): the per-face
/// directions of docs/TEXTURES.md, which are not always dp/du and dp/dv of shape_uv.
void shape_tangents(const Shape& shape, const glm::vec3& p, int face, glm::vec3& tangent_u, glm::vec3& tangent_v);

}  // namespace caustica
