// Helpers shared by the CSG tests (test_csg.cpp, test_csg_media.cpp): hand-made interval lists
// and small CSG scenes built node by node.
#pragma once

#include "core/geometry/csg_intervals.h"
#include "core/geometry/render_scene.h"
#include "core/scene/scene_flatten.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace caustica::csg_testing {

using caustica::testing::JobBuilder;

// ---- hand-made interval lists: the ray runs along +x, so entries face -x and exits +x ----

/// A segment [t0, t1] of one leaf with material (and medium) `material`.
inline CsgSegment segment(float t0, float t1, int material, int leaf = 0) {
    CsgSegment s;
    s.enter = {t0, {-1.0f, 0.0f, 0.0f}, material, leaf, 0, false};
    s.leave = {t1, {1.0f, 0.0f, 0.0f}, material, leaf, 1, false};
    s.medium = material;
    return s;
}

inline CsgSegmentList list(std::initializer_list<CsgSegment> segments) {
    CsgSegmentList l;
    for (const CsgSegment& s : segments) l.push_back(s);
    return l;
}

inline CsgSegmentList unite(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_union(a, b, eps, out);
    return out;
}
inline CsgSegmentList intersect(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_intersection(a, b, eps, out);
    return out;
}
inline CsgSegmentList subtract(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_difference(a, b, eps, out);
    return out;
}

/// Checks a result segment's extent, medium and the materials of its two surfaces.
inline void expect_segment(const CsgSegment& s, float t0, float t1, int medium, int enter_material, int leave_material) {
    EXPECT_EQ(s.enter.t, t0);
    EXPECT_EQ(s.leave.t, t1);
    EXPECT_EQ(s.medium, medium);
    EXPECT_EQ(s.enter.material, enter_material);
    EXPECT_EQ(s.leave.material, leave_material);
}

/// Checks the first boundary at or after tnear: its t, surface material, and the media on its sides.
inline void expect_boundary(const CsgSegmentList& l, float tnear, float t, int material, int inside, int outside) {
    CsgBoundary b;
    ASSERT_TRUE(csg_first_boundary(l, tnear, 100.0f, b)) << "from " << tnear;
    EXPECT_EQ(b.surface->t, t) << "from " << tnear;
    EXPECT_EQ(b.surface->material, material) << "from " << tnear;
    EXPECT_EQ(b.medium_inside, inside) << "from " << tnear;
    EXPECT_EQ(b.medium_outside, outside) << "from " << tnear;
}

inline constexpr int glass = 1, liquid = 2, red = 3;

// ---- CSG objects in the Embree scene ----

/// Adds a node that is not a child of anything (a CSG operand).
inline int operand(JobBuilder& b, NodeKind kind, int material = -1) {
    NodeDesc n;
    n.kind = kind;
    n.name = "operand" + std::to_string(b.scene->nodes.size());
    n.material = material;
    b.scene->nodes.push_back(n);
    return static_cast<int>(b.scene->nodes.size()) - 1;
}

/// Adds a CSG node over two operands under `parent` (-1: no parent).
inline int csg(JobBuilder& b, NodeKind kind, int left, int right, int parent = 0, int material = -1) {
    const int index = operand(b, kind, material);
    b.scene->nodes[index].csg_left = left;
    b.scene->nodes[index].csg_right = right;
    if (parent >= 0) b.scene->nodes[parent].children.push_back(index);
    return index;
}

inline int sphere_at(JobBuilder& b, glm::dvec3 centre, double radius, int material = -1) {
    const int s = operand(b, NodeKind::nh_sphere, material);
    b.scene->nodes[s].position = centre;
    b.scene->nodes[s].size = radius;
    return s;
}

/// Adds a transparent material with medium colour `kd` and refractive index `n`.
inline int dielectric(JobBuilder& b, glm::dvec3 kd, double n) {
    MaterialDesc m;
    m.kd = kd;
    m.ks = {0.9, 0.9, 0.9};
    m.refractive_index = n;
    b.scene->materials.push_back(m);
    return static_cast<int>(b.scene->materials.size()) - 1;
}

inline SurfaceHit trace(const RenderScene& scene, glm::vec3 origin, glm::vec3 direction, float tmin = 0.0f) {
    SurfaceHit hit;
    EXPECT_TRUE(scene.intersect(Ray{origin, glm::normalize(direction), tmin, ray_infinity}, hit))
        << "from " << origin.x << "," << origin.y << "," << origin.z;
    return hit;
}

inline bool misses(const RenderScene& scene, glm::vec3 origin, glm::vec3 direction, float tmin = 0.0f) {
    SurfaceHit hit;
    return !scene.intersect(Ray{origin, glm::normalize(direction), tmin, ray_infinity}, hit);
}

}  // namespace caustica::csg_testing
