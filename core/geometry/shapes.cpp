#include "core/geometry/shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustica {
namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();
constexpr float pi = 3.14159265358979323846f;

/// Roots of a t^2 + 2 bh t + c = 0 in increasing order, computed without cancellation.
/// `disc` is the already-robust discriminant bh^2 - a c (callers compute it from projected
/// distances so that it keeps its precision far from the shape).
void stable_roots(float a, float bh, float c, float disc, float& t0, float& t1) {
    float root = std::sqrt(disc);
    float q = -bh - std::copysign(root, bh);
    if (q == 0.0f) {
        t0 = t1 = -bh / a;
        return;
    }
    t0 = q / a;
    t1 = c / q;
    if (t0 > t1) std::swap(t0, t1);
}

bool sphere_interval(const Shape& s, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out) {
    const glm::vec3 centre = s.a;
    const float radius = s.b.x;
    const glm::vec3 oc = o - centre;
    const float a = glm::dot(d, d);
    const float bh = glm::dot(d, oc);
    // Squared distance from the centre to the line, computed directly rather than as bh^2 - a c.
    const glm::vec3 closest = oc - (bh / a) * d;
    const float disc = a * (radius - glm::length(closest)) * (radius + glm::length(closest));
    if (!(disc >= 0.0f)) return false;
    const float c = glm::dot(oc, oc) - radius * radius;
    float t0, t1;
    stable_roots(a, bh, c, disc, t0, t1);
    out.entry = {t0, o + t0 * d - centre, 0};
    out.exit = {t1, o + t1 * d - centre, 0};
    return true;
}

bool box_interval(const Shape& s, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out) {
    float t_enter = -infinity, t_exit = infinity;
    int face_enter = 0, face_exit = 1;
    for (int axis = 0; axis < 3; ++axis) {
        const float inv = 1.0f / d[axis];
        float t_lo = (s.a[axis] - o[axis]) * inv;
        float t_hi = (s.b[axis] - o[axis]) * inv;
        if (std::isnan(t_lo) || std::isnan(t_hi)) {  // parallel and exactly on a slab plane
            if (o[axis] < s.a[axis] || o[axis] > s.b[axis]) return false;
            continue;
        }
        int near_face = axis * 2, far_face = axis * 2 + 1;
        if (t_lo > t_hi) std::swap(t_lo, t_hi), std::swap(near_face, far_face);
        if (t_lo > t_enter) t_enter = t_lo, face_enter = near_face;
        if (t_hi < t_exit) t_exit = t_hi, face_exit = far_face;
    }
    if (!(t_enter <= t_exit)) return false;
    auto face_normal = [](int face) {
        glm::vec3 n(0.0f);
        n[face / 2] = (face % 2) ? 1.0f : -1.0f;
        return n;
    };
    out.entry = {t_enter, face_normal(face_enter), face_enter};
    out.exit = {t_exit, face_normal(face_exit), face_exit};
    return true;
}

/// The ray's interval inside the slab y in [lo, hi], with the cap crossing for each end.
bool slab_y(float lo, float hi, const glm::vec3& o, const glm::vec3& d, SurfaceCrossing& enter, SurfaceCrossing& leave) {
    if (d.y == 0.0f) {
        if (o.y < lo || o.y > hi) return false;
        enter = {-infinity, glm::vec3(0.0f), 0};
        leave = {infinity, glm::vec3(0.0f), 0};
        return true;
    }
    const float t_bottom = (lo - o.y) / d.y, t_top = (hi - o.y) / d.y;
    const SurfaceCrossing bottom{t_bottom, {0.0f, -1.0f, 0.0f}, 2};
    const SurfaceCrossing top{t_top, {0.0f, 1.0f, 0.0f}, 1};
    enter = d.y > 0.0f ? bottom : top;
    leave = d.y > 0.0f ? top : bottom;
    return true;
}

/// Intersects [enter, leave] with the slab interval; keeps the crossing that bounds the result.
bool clip_to_slab(SurfaceCrossing enter, SurfaceCrossing leave, const SurfaceCrossing& slab_enter,
                  const SurfaceCrossing& slab_leave, ShapeInterval& out) {
    if (slab_enter.t > enter.t) enter = slab_enter;
    if (slab_leave.t < leave.t) leave = slab_leave;
    if (!(enter.t <= leave.t) || std::isinf(enter.t) || std::isinf(leave.t)) return false;
    out.entry = enter;
    out.exit = leave;
    return true;
}

bool cylinder_interval(const Shape&, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out) {
    SurfaceCrossing slab_enter, slab_leave;
    if (!slab_y(-1.0f, 1.0f, o, d, slab_enter, slab_leave)) return false;
    const glm::vec2 o2(o.x, o.z), d2(d.x, d.z);
    const float a = glm::dot(d2, d2);
    SurfaceCrossing enter{-infinity, glm::vec3(0.0f), 0}, leave{infinity, glm::vec3(0.0f), 0};
    if (a > 0.0f) {
        const float bh = glm::dot(d2, o2);
        const float dist = glm::length(o2 - (bh / a) * d2);
        const float disc = a * (1.0f - dist) * (1.0f + dist);
        if (!(disc >= 0.0f)) return false;
        float t0, t1;
        stable_roots(a, bh, glm::dot(o2, o2) - 1.0f, disc, t0, t1);
        const glm::vec3 p0 = o + t0 * d, p1 = o + t1 * d;
        enter = {t0, {p0.x, 0.0f, p0.z}, 0};
        leave = {t1, {p1.x, 0.0f, p1.z}, 0};
    } else if (glm::dot(o2, o2) > 1.0f) {
        return false;  // parallel to the axis, outside
    }
    return clip_to_slab(enter, leave, slab_enter, slab_leave, out);
}

bool cone_interval(const Shape&, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out) {
    SurfaceCrossing slab_enter, slab_leave;
    if (!slab_y(-0.5f, 0.5f, o, d, slab_enter, slab_leave)) return false;
    // Double cone x^2 + z^2 = (1/2 - y)^2 with the apex at y = 1/2 (half-angle 45 degrees); the
    // slab y in [-1/2, 1/2] keeps the lower nappe: height 1, base radius 1 (docs/SCENE_LANGUAGE.md,
    // "cone").
    const float w0 = 0.5f - o.y;
    const float a = d.x * d.x + d.z * d.z - d.y * d.y;
    const float bh = o.x * d.x + o.z * d.z + w0 * d.y;
    const float c = o.x * o.x + o.z * o.z - w0 * w0;
    auto lateral = [&](float t) {
        const glm::vec3 p = o + t * d;
        return SurfaceCrossing{t, {p.x, 0.5f - p.y, p.z}, 0};
    };
    const SurfaceCrossing minus_inf{-infinity, glm::vec3(0.0f), 0}, plus_inf{infinity, glm::vec3(0.0f), 0};
    const float disc = bh * bh - a * c;
    if (a == 0.0f) {  // parallel to a generator: one half-line
        if (bh == 0.0f) {
            if (c > 0.0f) return false;
            return clip_to_slab(minus_inf, plus_inf, slab_enter, slab_leave, out);
        }
        const float t = -c / (2.0f * bh);
        return bh > 0.0f ? clip_to_slab(minus_inf, lateral(t), slab_enter, slab_leave, out)
                         : clip_to_slab(lateral(t), plus_inf, slab_enter, slab_leave, out);
    }
    if (disc < 0.0f) {
        if (a > 0.0f) return false;
        return clip_to_slab(minus_inf, plus_inf, slab_enter, slab_leave, out);
    }
    float t0, t1;
    stable_roots(a, bh, c, disc, t0, t1);
    if (a > 0.0f) return clip_to_slab(lateral(t0), lateral(t1), slab_enter, slab_leave, out);
    // a < 0: inside on (-inf, t0] and [t1, inf); one piece is on the upper nappe, outside the slab.
    ShapeInterval first, second;
    const bool has_first = clip_to_slab(minus_inf, lateral(t0), slab_enter, slab_leave, first);
    const bool has_second = clip_to_slab(lateral(t1), plus_inf, slab_enter, slab_leave, second);
    if (has_first && has_second) {
        out = (first.exit.t - first.entry.t >= second.exit.t - second.entry.t) ? first : second;
        return true;
    }
    if (has_first) out = first;
    if (has_second) out = second;
    return has_first || has_second;
}

}  // namespace

bool intersect_shape_interval(const Shape& shape, const glm::vec3& o, const glm::vec3& d, ShapeInterval& out) {
    switch (shape.kind) {
        case ShapeKind::sphere: return sphere_interval(shape, o, d, out);
        case ShapeKind::box: return box_interval(shape, o, d, out);
        case ShapeKind::cylinder: return cylinder_interval(shape, o, d, out);
        case ShapeKind::cone: return cone_interval(shape, o, d, out);
    }
    return false;
}

void shape_bounds(const Shape& shape, glm::vec3& lo, glm::vec3& hi) {
    switch (shape.kind) {
        case ShapeKind::sphere:
            lo = shape.a - glm::vec3(shape.b.x);
            hi = shape.a + glm::vec3(shape.b.x);
            return;
        case ShapeKind::box:
            lo = shape.a;
            hi = shape.b;
            return;
        case ShapeKind::cylinder:
            lo = glm::vec3(-1.0f);
            hi = glm::vec3(1.0f);
            return;
        case ShapeKind::cone:
            lo = glm::vec3(-1.0f, -0.5f, -1.0f);
            hi = glm::vec3(1.0f, 0.5f, 1.0f);
            return;
    }
}

namespace {

// Box face codes (SurfaceCrossing::face) and cylinder/cone faces.
constexpr int face_minus_x = 0, face_plus_x = 1, face_minus_y = 2, face_plus_y = 3, face_minus_z = 4;
constexpr int face_side = 0, face_top_cap = 1;

/// u around the y axis of the cylinder and cone sides: 1/2 + atan2(z, x) / 2 pi.
float around_y(const glm::vec3& p) { return 0.5f + std::atan2(p.z, p.x) / (2.0f * pi); }

/// The cube's 4 x 3 cross (docs/TEXTURES.md), from s = the point's position in the box, in [0,1]^3.
glm::vec2 box_uv(const glm::vec3& s, int face) {
    switch (face) {
        case face_plus_x: return {(3.0f - s.y) / 4.0f, (2.0f - s.z) / 3.0f};
        case face_minus_x: return {s.y / 4.0f, (2.0f - s.z) / 3.0f};
        case face_plus_y: return {(1.0f + s.x) / 4.0f, (2.0f - s.z) / 3.0f};
        case face_minus_y: return {(4.0f - s.x) / 4.0f, (2.0f - s.z) / 3.0f};
        case face_minus_z: return {(1.0f + s.x) / 4.0f, (3.0f - s.y) / 3.0f};
        default: return {(1.0f + s.x) / 4.0f, s.y / 3.0f};  // +z
    }
}

/// The cube's tangents (docs/TEXTURES.md): U and V per face.
void box_tangents(int face, glm::vec3& tangent_u, glm::vec3& tangent_v) {
    switch (face) {
        case face_plus_x: tangent_u = {0, -1, 0}, tangent_v = {0, 0, -1}; return;
        case face_minus_x: tangent_u = {0, 1, 0}, tangent_v = {0, 0, -1}; return;
        case face_plus_y: tangent_u = {1, 0, 0}, tangent_v = {0, 0, -1}; return;
        case face_minus_y: tangent_u = {-1, 0, 0}, tangent_v = {0, 0, -1}; return;
        case face_minus_z: tangent_u = {1, 0, 0}, tangent_v = {0, -1, 0}; return;
        default: tangent_u = {1, 0, 0}, tangent_v = {0, 1, 0}; return;  // +z
    }
}

/// `v` at unit length, or zero when it has no direction.
glm::vec3 unit_or_zero(const glm::vec3& v) {
    const float length = glm::length(v);
    return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f);
}

}  // namespace

glm::vec2 shape_uv(const Shape& shape, const glm::vec3& p, int face) {
    switch (shape.kind) {
        case ShapeKind::sphere: {
            // u = 1/2 + atan2(-z, x) / 2 pi (seam at -x, +z at u = 1/4), v = (1 + y) / 2.
            const glm::vec3 q = (p - shape.a) / shape.b.x;
            return {0.5f + std::atan2(-q.z, q.x) / (2.0f * pi), std::clamp(0.5f * (1.0f + q.y), 0.0f, 1.0f)};
        }
        case ShapeKind::box:
            return box_uv(glm::clamp((p - shape.a) / (shape.b - shape.a), 0.0f, 1.0f), face);
        case ShapeKind::cylinder:
            if (face == face_side) return {around_y(p), std::clamp(0.25f * (1.0f - p.y), 0.0f, 0.5f)};
            if (face == face_top_cap) return {0.25f * (3.0f + p.x), 0.25f * (3.0f + p.z)};
            return {0.25f * (1.0f + p.x), 0.25f * (3.0f + p.z)};
        case ShapeKind::cone:
            if (face == face_side) return {around_y(p), std::clamp(0.5f * (0.5f - p.y), 0.0f, 0.5f)};
            return {0.5f * (1.0f + p.x), 0.25f * (3.0f + p.z)};
    }
    return {0.0f, 0.0f};
}

void shape_tangents(const Shape& shape, const glm::vec3& p, int face, glm::vec3& tangent_u, glm::vec3& tangent_v) {
    switch (shape.kind) {
        case ShapeKind::sphere: {
            // U = normalise(y, 0, -x): zero at (0, 0, +-1), where the original has no tangent.
            const glm::vec3 q = (p - shape.a) / shape.b.x;
            tangent_u = unit_or_zero({q.y, 0.0f, -q.x});
            tangent_v = unit_or_zero(glm::cross(unit_or_zero(q), tangent_u));
            return;
        }
        case ShapeKind::box: box_tangents(face, tangent_u, tangent_v); return;
        case ShapeKind::cylinder:
            if (face != face_side) {
                tangent_u = {1, 0, 0}, tangent_v = {0, 0, 1};
                return;
            }
            tangent_u = unit_or_zero({-p.z, 0.0f, p.x});  // along increasing u
            tangent_v = {0, -1, 0};
            return;
        case ShapeKind::cone:
            if (face != face_side) {
                tangent_u = {1, 0, 0}, tangent_v = {0, 0, 1};
                return;
            }
            // V: towards the apex; U = V x N (the outward normal is (x, 1/2 - y, z) normalised).
            tangent_v = unit_or_zero(glm::vec3(0.0f, 0.5f, 0.0f) - p);
            tangent_u = unit_or_zero(glm::cross(tangent_v, unit_or_zero({p.x, 0.5f - p.y, p.z})));
            return;
    }
    tangent_u = tangent_v = glm::vec3(0.0f);
}

}  // namespace caustica
