// Constructive solid geometry: the interval algebra on hand-made lists, CSG objects traced
// through the Embree scene against analytic answers, and render invariances.
#include "core/scene/camera.h"
#include "core/geometry/csg_intervals.h"
#include "core/integrators/integrator.h"
#include "core/lua/scene_loader.h"
#include "core/geometry/render_scene.h"
#include "core/scene/scene_flatten.h"
#include "core/render/tile_renderer.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

// ---- hand-made interval lists: the ray runs along +x, so entries face -x and exits +x ----

/// A segment [t0, t1] of one leaf with material (and medium) `material`.
CsgSegment segment(float t0, float t1, int material, int leaf = 0) {
    CsgSegment s;
    s.enter = {t0, {-1.0f, 0.0f, 0.0f}, material, leaf, 0, false};
    s.leave = {t1, {1.0f, 0.0f, 0.0f}, material, leaf, 1, false};
    s.medium = material;
    return s;
}

CsgSegmentList list(std::initializer_list<CsgSegment> segments) {
    CsgSegmentList l;
    for (const CsgSegment& s : segments) l.push_back(s);
    return l;
}

CsgSegmentList unite(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_union(a, b, eps, out);
    return out;
}
CsgSegmentList intersect(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_intersection(a, b, eps, out);
    return out;
}
CsgSegmentList subtract(const CsgSegmentList& a, const CsgSegmentList& b, float eps = 0.0f) {
    CsgSegmentList out;
    csg_difference(a, b, eps, out);
    return out;
}

/// Checks a result segment's extent, medium and the materials of its two surfaces.
void expect_segment(const CsgSegment& s, float t0, float t1, int medium, int enter_material, int leave_material) {
    EXPECT_EQ(s.enter.t, t0);
    EXPECT_EQ(s.leave.t, t1);
    EXPECT_EQ(s.medium, medium);
    EXPECT_EQ(s.enter.material, enter_material);
    EXPECT_EQ(s.leave.material, leave_material);
}

/// Checks the first boundary at or after tnear: its t, surface material, and the media on its sides.
void expect_boundary(const CsgSegmentList& l, float tnear, float t, int material, int inside, int outside) {
    CsgBoundary b;
    ASSERT_TRUE(csg_first_boundary(l, tnear, 100.0f, b)) << "from " << tnear;
    EXPECT_EQ(b.surface->t, t) << "from " << tnear;
    EXPECT_EQ(b.surface->material, material) << "from " << tnear;
    EXPECT_EQ(b.medium_inside, inside) << "from " << tnear;
    EXPECT_EQ(b.medium_outside, outside) << "from " << tnear;
}

constexpr int glass = 1, liquid = 2, red = 3;

}  // namespace

TEST(CsgIntervals, DisjointListsUniteAsTheyAre) {
    const CsgSegmentList u = unite(list({segment(0, 1, red)}), list({segment(2, 3, glass)}));
    ASSERT_EQ(u.size(), 2);
    expect_segment(u[0], 0, 1, red, red, red);
    expect_segment(u[1], 2, 3, glass, glass, glass);
    EXPECT_TRUE(intersect(list({segment(0, 1, red)}), list({segment(2, 3, glass)})).empty());
    const CsgSegmentList d = subtract(list({segment(0, 1, red)}), list({segment(2, 3, glass)}));
    ASSERT_EQ(d.size(), 1);
    expect_segment(d[0], 0, 1, red, red, red);
}

TEST(CsgIntervals, OverlappingSegmentsTakeTheBoundingOperandsSurfaces) {
    const CsgSegmentList a = list({segment(0, 5, red, 0)}), b = list({segment(3, 8, glass, 1)});
    const CsgSegmentList i = intersect(a, b);
    ASSERT_EQ(i.size(), 1);
    expect_segment(i[0], 3, 5, red, glass, red);  // entered through b, left through a; medium of a
    EXPECT_EQ(i[0].enter.leaf, 1);
    EXPECT_EQ(i[0].leave.leaf, 0);
    // Same medium: one segment from a's entry to b's exit.
    const CsgSegmentList u = unite(a, list({segment(3, 8, red, 1)}));
    ASSERT_EQ(u.size(), 1);
    expect_segment(u[0], 0, 8, red, red, red);
    EXPECT_EQ(u[0].enter.leaf, 0);
    EXPECT_EQ(u[0].leave.leaf, 1);
}

TEST(CsgIntervals, NestedSegments) {
    const CsgSegmentList outer = list({segment(0, 10, red, 0)}), inner = list({segment(2, 3, red, 1)});
    const CsgSegmentList u = unite(outer, inner);
    ASSERT_EQ(u.size(), 1);
    expect_segment(u[0], 0, 10, red, red, red);
    const CsgSegmentList i = intersect(outer, inner);
    ASSERT_EQ(i.size(), 1);
    EXPECT_EQ(i[0].enter.leaf, 1);
    EXPECT_EQ(i[0].leave.leaf, 1);
    EXPECT_TRUE(subtract(inner, outer).empty());
}

TEST(CsgIntervals, DifferenceSplitsAndFlipsTheSubtractedSurfaces) {
    const CsgSegmentList a = list({segment(0, 10, red, 0)}), b = list({segment(4, 6, glass, 1)});
    const CsgSegmentList d = subtract(a, b);
    ASSERT_EQ(d.size(), 2);
    expect_segment(d[0], 0, 4, red, red, glass);
    expect_segment(d[1], 6, 10, red, glass, red);
    // The hole's walls are b's surfaces seen from outside b: normals flipped.
    EXPECT_EQ(d[0].leave.normal, -b[0].enter.normal);
    EXPECT_EQ(d[1].enter.normal, -b[0].leave.normal);
    EXPECT_EQ(d[0].leave.normal, glm::vec3(1, 0, 0));  // still pointing out of the remaining solid
    EXPECT_EQ(d[1].enter.normal, glm::vec3(-1, 0, 0));
    EXPECT_EQ(d[0].enter.normal, a[0].enter.normal);
    EXPECT_EQ(d[0].leave.leaf, 1);
}

TEST(CsgIntervals, CoincidentOperands) {
    const CsgSegmentList a = list({segment(2, 6, red, 0), segment(8, 9, red, 0)});
    EXPECT_TRUE(subtract(a, a).empty());
    for (const CsgSegmentList& r : {unite(a, a), intersect(a, a)}) {
        ASSERT_EQ(r.size(), 2);
        expect_segment(r[0], 2, 6, red, red, red);
        expect_segment(r[1], 8, 9, red, red, red);
    }
    // Same shape, different media: the second operand fills it, with its own surfaces.
    const CsgSegmentList u = unite(list({segment(2, 6, glass, 0)}), list({segment(2, 6, liquid, 1)}));
    ASSERT_EQ(u.size(), 1);
    expect_segment(u[0], 2, 6, liquid, liquid, liquid);
    EXPECT_FALSE(u[0].enter.mirrored || u[0].leave.mirrored);
}

TEST(CsgIntervals, SharedFacesAndTangentContacts) {
    // Two boxes sharing a face: one solid in a union, nothing in an intersection, and a
    // difference keeps the first box's own face.
    const CsgSegmentList left = list({segment(0, 1, red, 0)}), right = list({segment(1, 2, red, 1)});
    const CsgSegmentList u = unite(left, right);
    ASSERT_EQ(u.size(), 1);
    expect_segment(u[0], 0, 2, red, red, red);
    EXPECT_TRUE(intersect(left, right).empty());
    const CsgSegmentList d = subtract(left, right);
    ASSERT_EQ(d.size(), 1);
    EXPECT_EQ(d[0].leave.leaf, 0);
    EXPECT_EQ(d[0].leave.normal, glm::vec3(1, 0, 0));
    const CsgSegmentList d2 = subtract(right, left);
    ASSERT_EQ(d2.size(), 1);
    EXPECT_EQ(d2[0].enter.leaf, 1);
    // A ray grazing a sphere: a zero-length segment. It survives union and intersection with a
    // solid around it, and subtracting it from a solid changes nothing.
    const CsgSegmentList graze = list({segment(1, 1, glass, 1)}), around = list({segment(0, 2, red, 0)});
    ASSERT_EQ(unite(graze, list({segment(3, 4, glass, 2)})).size(), 2);
    const CsgSegmentList i = intersect(graze, around);
    ASSERT_EQ(i.size(), 1);
    EXPECT_EQ(i[0].enter.t, 1.0f);
    EXPECT_EQ(i[0].leave.t, 1.0f);
    const CsgSegmentList kept = subtract(around, graze);
    ASSERT_EQ(kept.size(), 1);
    expect_segment(kept[0], 0, 2, red, red, red);
}

TEST(CsgIntervals, EmptyOperands) {
    const CsgSegmentList a = list({segment(0, 1, red)}), none{};
    EXPECT_EQ(unite(none, a).size(), 1);
    EXPECT_EQ(unite(a, none).size(), 1);
    EXPECT_TRUE(intersect(a, none).empty());
    EXPECT_TRUE(intersect(none, a).empty());
    EXPECT_EQ(subtract(a, none).size(), 1);
    EXPECT_TRUE(subtract(none, a).empty());
    EXPECT_TRUE(unite(none, none).empty());
}

TEST(CsgIntervals, SliversWithinEpsilonAreDropped) {
    // Coincident faces that rounding has separated by less than epsilon leave nothing behind.
    const CsgSegmentList a = list({segment(0, 10, red, 0)});
    const CsgSegmentList b = list({segment(1e-6f, 10 - 1e-6f, red, 1)});
    EXPECT_EQ(subtract(a, b, 0.0f).size(), 2);
    EXPECT_TRUE(subtract(a, b, 1e-5f).empty());
    EXPECT_TRUE(intersect(a, list({segment(10 - 1e-6f, 20, red, 1)}), 1e-5f).empty());
    // But an input segment shorter than epsilon (a chord near a sphere's rim) is kept.
    EXPECT_EQ(unite(list({segment(5, 5 + 1e-6f, red)}), CsgSegmentList{}, 1e-5f).size(), 1);
    EXPECT_EQ(intersect(list({segment(5, 5 + 1e-6f, red)}), a, 1e-5f).size(), 1);
}

TEST(CsgIntervals, UnionRecordsInterfacesWhereTheSecondOperandBeginsAndEnds) {
    // A glass with liquid inside: the liquid (second operand) begins and ends inside the glass.
    const CsgSegmentList u = unite(list({segment(0, 10, glass, 0)}), list({segment(2, 6, liquid, 1)}));
    ASSERT_EQ(u.size(), 3);
    expect_segment(u[0], 0, 2, glass, glass, liquid);
    expect_segment(u[1], 2, 6, liquid, liquid, liquid);
    expect_segment(u[2], 6, 10, glass, liquid, glass);
    // Exactly one end of each touching pair is the real surface: the liquid's.
    EXPECT_TRUE(u[0].leave.mirrored && u[2].enter.mirrored);
    EXPECT_FALSE(u[1].enter.mirrored || u[1].leave.mirrored);
    expect_boundary(u, -5, 0, glass, glass, -1);      // air -> glass
    expect_boundary(u, 1, 2, liquid, liquid, glass);  // glass -> liquid
    expect_boundary(u, 3, 6, liquid, liquid, glass);  // liquid -> glass
    expect_boundary(u, 7, 10, glass, glass, -1);      // glass -> air
    // The interface normals point from the liquid (inside) to the glass.
    CsgBoundary b;
    ASSERT_TRUE(csg_first_boundary(u, 1, 100, b));
    EXPECT_EQ(b.surface->normal, glm::vec3(-1, 0, 0));
    ASSERT_TRUE(csg_first_boundary(u, 3, 100, b));
    EXPECT_EQ(b.surface->normal, glm::vec3(1, 0, 0));
    EXPECT_FALSE(csg_first_boundary(u, 7, 9, b));  // nothing before tfar
}

TEST(CsgIntervals, TheSecondOperandWinsWhereTheyOverlap) {
    const CsgSegmentList a = list({segment(0, 5, glass, 0)}), b = list({segment(3, 8, liquid, 1)});
    const CsgSegmentList ab = unite(a, b);
    ASSERT_EQ(ab.size(), 2);
    expect_segment(ab[0], 0, 3, glass, glass, liquid);
    expect_segment(ab[1], 3, 8, liquid, liquid, liquid);
    const CsgSegmentList ba = unite(b, a);
    ASSERT_EQ(ba.size(), 2);
    expect_segment(ba[0], 0, 5, glass, glass, glass);
    expect_segment(ba[1], 5, 8, liquid, glass, liquid);
    expect_boundary(ba, 1, 5, glass, glass, liquid);  // the glass's exit surface is the real one
    // A first operand inside the second vanishes.
    const CsgSegmentList covered = unite(list({segment(2, 3, liquid, 1)}), list({segment(0, 10, glass, 0)}));
    ASSERT_EQ(covered.size(), 1);
    expect_segment(covered[0], 0, 10, glass, glass, glass);
}

TEST(CsgIntervals, UnionInterfaceWithinEpsilonOfTheOthersBeginning) {
    const float eps = 1e-5f, gap = 1e-6f;
    const CsgSegmentList a = list({segment(0, 5, glass, 0)}), b = list({segment(5 + gap, 8, liquid, 1)});
    expect_boundary(unite(a, b, 0.0f), 1, 5, glass, glass, -1);  // no tolerance: the gap is air
    // Within epsilon the segments touch at the liquid's surface.
    const CsgSegmentList u = unite(a, b, eps);
    ASSERT_EQ(u.size(), 2);
    EXPECT_EQ(u[0].leave.t, u[1].enter.t);
    expect_boundary(u, 1, 5 + gap, liquid, liquid, glass);
    // The second operand ending within epsilon of the first's beginning: its own exit surface.
    const CsgSegmentList v = unite(list({segment(5 + gap, 8, glass, 0)}), list({segment(0, 5, liquid, 1)}), eps);
    ASSERT_EQ(v.size(), 2);
    expect_boundary(v, 1, 5, liquid, liquid, glass);
    EXPECT_EQ(v[0].leave.normal, glm::vec3(1, 0, 0));
    // Equal media within epsilon simply join.
    EXPECT_EQ(unite(a, list({segment(5 + gap, 8, glass, 1)}), eps).size(), 1);
}

TEST(CsgIntervals, InterfacesSurviveNestedOperations) {
    const CsgSegmentList cup = unite(list({segment(0, 10, glass, 0)}), list({segment(2, 6, liquid, 1)}));
    // Cut by a box: the liquid's interfaces are kept, the glass is trimmed.
    const CsgSegmentList cut = intersect(cup, list({segment(1, 9, red, 2)}));
    ASSERT_EQ(cut.size(), 3);
    expect_segment(cut[0], 1, 2, glass, red, liquid);
    expect_segment(cut[1], 2, 6, liquid, liquid, liquid);
    expect_segment(cut[2], 6, 9, glass, liquid, red);
    expect_boundary(cut, 1.5f, 2, liquid, liquid, glass);
    // United with something else further on: unchanged.
    const CsgSegmentList more = unite(cup, list({segment(20, 21, red, 3)}));
    ASSERT_EQ(more.size(), 4);
    EXPECT_TRUE(more[0].leave.mirrored && more[2].enter.mirrored);
    // A third operand replacing the liquid's end: the new interface is the new operand's surface.
    const CsgSegmentList three = unite(cup, list({segment(6, 7, red, 3)}));
    ASSERT_EQ(three.size(), 4);
    expect_boundary(three, 3, 6, red, red, liquid);
}

TEST(CsgIntervals, RayStartingInsideFindsTheExit) {
    const CsgSegmentList l = list({segment(-2, 3, red), segment(5, 6, red)});
    expect_boundary(l, 0, 3, red, red, -1);
    expect_boundary(l, 3.5f, 5, red, red, -1);
    CsgBoundary b;
    EXPECT_FALSE(csg_first_boundary(l, 6.5f, 100.0f, b));
}

TEST(CsgIntervals, ListsMoveToTheHeapOnlyBeyondTheInlineCapacity) {
    CsgSegmentList l;
    for (int i = 0; i < CsgSegmentList::inline_capacity; ++i) l.push_back(segment(float(i), float(i) + 0.5f, red));
    EXPECT_FALSE(l.on_heap());
    for (int i = CsgSegmentList::inline_capacity; i < 40; ++i) l.push_back(segment(float(i), float(i) + 0.5f, red));
    EXPECT_TRUE(l.on_heap());
    const CsgSegmentList copy = l;
    ASSERT_EQ(copy.size(), 40);
    EXPECT_EQ(copy[39].enter.t, 39.0f);
    // Big lists combine like small ones: every other segment removed.
    CsgSegmentList odd;
    for (int i = 1; i < 40; i += 2) odd.push_back(segment(float(i), float(i) + 0.5f, red));
    const CsgSegmentList even = subtract(l, odd);
    ASSERT_EQ(even.size(), 20);
    for (int i = 0; i < 20; ++i) EXPECT_EQ(even[i].enter.t, float(2 * i));
}

// ---- CSG objects in the Embree scene ----

namespace {

/// Adds a node that is not a child of anything (a CSG operand).
int operand(JobBuilder& b, NodeKind kind, int material = -1) {
    NodeDesc n;
    n.kind = kind;
    n.name = "operand" + std::to_string(b.scene->nodes.size());
    n.material = material;
    b.scene->nodes.push_back(n);
    return static_cast<int>(b.scene->nodes.size()) - 1;
}

/// Adds a CSG node over two operands under `parent` (-1: no parent).
int csg(JobBuilder& b, NodeKind kind, int left, int right, int parent = 0, int material = -1) {
    const int index = operand(b, kind, material);
    b.scene->nodes[index].csg_left = left;
    b.scene->nodes[index].csg_right = right;
    if (parent >= 0) b.scene->nodes[parent].children.push_back(index);
    return index;
}

int sphere_at(JobBuilder& b, glm::dvec3 centre, double radius, int material = -1) {
    const int s = operand(b, NodeKind::nh_sphere, material);
    b.scene->nodes[s].position = centre;
    b.scene->nodes[s].size = radius;
    return s;
}

/// Adds a transparent material with medium colour `kd` and refractive index `n`.
int dielectric(JobBuilder& b, glm::dvec3 kd, double n) {
    MaterialDesc m;
    m.kd = kd;
    m.ks = {0.9, 0.9, 0.9};
    m.refractive_index = n;
    b.scene->materials.push_back(m);
    return static_cast<int>(b.scene->materials.size()) - 1;
}

SurfaceHit trace(const RenderScene& scene, glm::vec3 origin, glm::vec3 direction, float tmin = 0.0f) {
    SurfaceHit hit;
    EXPECT_TRUE(scene.intersect(Ray{origin, glm::normalize(direction), tmin, ray_infinity}, hit))
        << "from " << origin.x << "," << origin.y << "," << origin.z;
    return hit;
}

bool misses(const RenderScene& scene, glm::vec3 origin, glm::vec3 direction, float tmin = 0.0f) {
    SurfaceHit hit;
    return !scene.intersect(Ray{origin, glm::normalize(direction), tmin, ray_infinity}, hit);
}

/// A biconvex lens: the intersection of two unit spheres centred at z = +-0.6 (faces at z = +-0.4).
struct Lens {
    JobBuilder b{8, 8};
    int front_material = b.material({1, 0, 0});
    int back_material = b.material({0, 0, 1});
    Lens() {
        const int back = sphere_at(b, {0, 0, 0.6}, 1.0, back_material);     // bounds the back face
        const int front = sphere_at(b, {0, 0, -0.6}, 1.0, front_material);  // bounds the front face
        csg(b, NodeKind::csg_intersection, back, front);
    }
};

}  // namespace

TEST(CsgScene, FlattenMakesOneObjectAndNoStandalonePrimitives) {
    Lens lens;
    const FlatScene flat = flatten_scene(*lens.b.scene, 0, false);
    EXPECT_TRUE(flat.primitives.empty());
    ASSERT_EQ(flat.csg_objects.size(), 1u);
    EXPECT_EQ(flat.csg_objects[0].leaves.size(), 2u);
    const RenderScene scene(*lens.b.scene, flat);
    EXPECT_EQ(scene.info().csg_objects, 1u);
    EXPECT_EQ(scene.info().analytic_primitives, 0u);
}

TEST(CsgScene, LensHitsAtTheAnalyticDistances) {
    Lens lens;
    const RenderScene scene(*lens.b.scene, flatten_scene(*lens.b.scene, 0, false));
    // On the axis: the front face at z = 0.4, bounded by the sphere centred at -0.6.
    SurfaceHit hit = trace(scene, {0, 0, 5}, {0, 0, -1});
    EXPECT_NEAR(hit.t, 4.6f, 1e-5f);
    EXPECT_NEAR(hit.normal.z, 1.0f, 1e-6f);
    EXPECT_EQ(hit.material, lens.front_material);
    EXPECT_EQ(hit.medium_inside, lens.back_material);  // the lens's medium: the first operand's
    EXPECT_EQ(hit.medium_outside, -1);
    // Off the axis at x = 0.3: z = -0.6 + sqrt(1 - 0.09), normal from that sphere's centre.
    hit = trace(scene, {0.3f, 0, 5}, {0, 0, -1});
    const float z = -0.6f + std::sqrt(1.0f - 0.09f);
    EXPECT_NEAR(hit.t, 5.0f - z, 1e-5f);
    const glm::vec3 expected = glm::normalize(glm::vec3(0.3f, 0.0f, z + 0.6f));
    EXPECT_NEAR(glm::dot(hit.normal, expected), 1.0f, 1e-6f);
    // From the other side: the back face at z = -0.4.
    hit = trace(scene, {0, 0, -5}, {0, 0, 1});
    EXPECT_NEAR(hit.t, 4.6f, 1e-5f);
    EXPECT_EQ(hit.material, lens.back_material);
    // Outside the lens rim (radius sqrt(1 - 0.36) = 0.8) both spheres are hit, but not together.
    EXPECT_TRUE(misses(scene, {0.85f, 0, 5}, {0, 0, -1}));
}

TEST(CsgScene, RayStartingInsideFindsTheExit) {
    Lens lens;
    const RenderScene scene(*lens.b.scene, flatten_scene(*lens.b.scene, 0, false));
    SurfaceHit hit = trace(scene, {0, 0, 0}, {0, 0, -1}, scene.epsilon());
    EXPECT_NEAR(hit.t, 0.4f, 1e-6f);
    EXPECT_NEAR(hit.normal.z, -1.0f, 1e-6f);  // outward: along the ray
    EXPECT_EQ(hit.material, lens.back_material);
    // A shadow ray from inside is blocked by the exit, unless it ends before it.
    EXPECT_TRUE(scene.occluded(Ray{{0, 0, 0}, {0, 0, 1}, scene.epsilon(), 10.0f}));
    EXPECT_FALSE(scene.occluded(Ray{{0, 0, 0}, {0, 0, 1}, scene.epsilon(), 0.3f}));
    // From a point just inside the front face, the refracted-ray case.
    hit = trace(scene, {0, 0, 0.4f}, {0.1f, 0, -1}, scene.epsilon());
    EXPECT_LT(hit.position.z, -0.3f);
}

TEST(CsgScene, BoxMinusCylinderHasAHoleToSeeThrough) {
    JobBuilder b(8, 8);
    const int grey = b.material({0.5, 0.5, 0.5}), blue = b.material({0, 0, 1});
    const int cube = operand(b, NodeKind::cube);  // [-1,1]^3, material inherited from the CSG node
    const int hole = operand(b, NodeKind::cylinder, blue);
    b.scale(hole, {0.3, 2.0, 0.3});  // radius 0.3 along y, longer than the cube
    csg(b, NodeKind::csg_difference, cube, hole, 0, grey);
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    EXPECT_TRUE(misses(scene, {0, 5, 0}, {0, -1, 0}));         // down the hole
    EXPECT_TRUE(misses(scene, {0.2f, 5, -0.1f}, {0, -1, 0}));
    SurfaceHit hit = trace(scene, {0.5f, 5, 0}, {0, -1, 0});  // beside it: the top face
    EXPECT_NEAR(hit.t, 4.0f, 1e-5f);
    EXPECT_EQ(hit.material, grey);
    EXPECT_NEAR(hit.normal.y, 1.0f, 1e-6f);
    // Across the cube through the middle: the hole's wall at x = 0.3 facing +x, blue.
    hit = trace(scene, {0.9f, 0, 0}, {-1, 0, 0}, 1e-4f);
    EXPECT_NEAR(hit.position.x, 0.3f, 1e-5f);
    EXPECT_NEAR(hit.normal.x, -1.0f, 1e-6f);  // out of the solid, into the hole
    EXPECT_EQ(hit.material, blue);
    hit = trace(scene, {0, 0, 0}, {-1, 0, 0}, 1e-4f);  // from inside the hole: the far wall
    EXPECT_NEAR(hit.position.x, -0.3f, 1e-5f);
    EXPECT_NEAR(hit.normal.x, 1.0f, 1e-6f);
    EXPECT_EQ(hit.shape_kind, static_cast<int>(ShapeKind::cylinder));
    EXPECT_EQ(hit.face, 0);  // the cylinder's side
}

TEST(CsgScene, UnionOfBoxesSharingAFaceIsOneSolid) {
    JobBuilder b(8, 8);
    const int m = b.material({1, 1, 1});
    const int left = operand(b, NodeKind::cube, m), right = operand(b, NodeKind::cube, m);
    b.translate(left, {-1, 0, 0});
    b.translate(right, {1, 0, 0});
    csg(b, NodeKind::csg_union, left, right);
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    SurfaceHit hit = trace(scene, {-5, 0.2f, 0.1f}, {1, 0, 0});
    EXPECT_NEAR(hit.position.x, -2.0f, 1e-5f);
    hit = trace(scene, {-1, 0.2f, 0.1f}, {1, 0, 0}, scene.epsilon());
    EXPECT_NEAR(hit.position.x, 2.0f, 1e-5f);  // no wall at x = 0
}

TEST(CsgScene, UnionRecordsTheGlassLiquidInterface) {
    JobBuilder b(8, 8);
    const int glass_m = dielectric(b, {0, 0, 0}, 1.5), liquid_m = dielectric(b, {0.8, 0.2, 0.2}, 1.33);
    const int vessel = operand(b, NodeKind::cube, glass_m);  // glass block [-1,1]^3
    const int drop = sphere_at(b, {0, 0, 0}, 0.5, liquid_m);  // liquid ball inside it
    csg(b, NodeKind::csg_union, vessel, drop);
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    // Down the z axis, each ray starting where the last stopped (as refracted rays do).
    struct Stop {
        float z, normal_z;
        int material, inside, outside;
    };
    const Stop stops[] = {{1.0f, 1.0f, glass_m, glass_m, -1},             // air -> glass
                          {0.5f, 1.0f, liquid_m, liquid_m, glass_m},      // glass -> liquid
                          {-0.5f, -1.0f, liquid_m, liquid_m, glass_m},    // liquid -> glass
                          {-1.0f, -1.0f, glass_m, glass_m, -1}};          // glass -> air
    glm::vec3 from(0, 0, 5);
    float tmin = 0.0f;
    for (const Stop& stop : stops) {
        const SurfaceHit hit = trace(scene, from, {0, 0, -1}, tmin);
        EXPECT_NEAR(hit.position.z, stop.z, 1e-5f);
        EXPECT_NEAR(hit.normal.z, stop.normal_z, 1e-6f);  // from the inside medium to the outside one
        EXPECT_EQ(hit.material, stop.material);
        EXPECT_EQ(hit.medium_inside, stop.inside);
        EXPECT_EQ(hit.medium_outside, stop.outside);
        from = hit.position;
        tmin = scene.epsilon();
    }
}

TEST(CsgScene, MeshOperandSubtractedFromASphere) {
    JobBuilder b(8, 8);
    const int grey = b.material({0.5, 0.5, 0.5}), green = b.material({0, 1, 0});
    // A closed cube [-0.5,0.5]^3 with counter-clockwise (outward) triangles.
    auto mesh = std::make_shared<MeshData>();
    mesh->path = "cube";
    for (int i = 0; i < 8; ++i)
        mesh->positions.push_back({(i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f});
    const glm::uvec3 faces[12] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5},   // -x, +x
                                  {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},   // -y, +y
                                  {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};  // -z, +z
    for (const glm::uvec3& f : faces) {
        const glm::vec3 v0 = mesh->positions[f.x], v1 = mesh->positions[f.y], v2 = mesh->positions[f.z];
        const glm::vec3 centre = (v0 + v1 + v2) / 3.0f;
        ASSERT_GT(glm::dot(glm::cross(v1 - v0, v2 - v0), centre), 0.0f);  // really outward
        mesh->triangles.push_back(f);
    }
    b.scene->meshes.push_back(mesh);
    const int ball = sphere_at(b, {0, 0, 0}, 1.0, grey);
    const int box = operand(b, NodeKind::mesh, green);
    b.scene->nodes[box].mesh = 0;
    b.translate(box, {1, 0, 0});  // x in [0.5, 1.5]: bites into the ball
    csg(b, NodeKind::csg_difference, ball, box);
    // Surface frames (object position, uv, tangents) are filled only in scenes with textures.
    TextureDesc checker;
    checker.source = "greencheck";
    checker.procedural = true;
    b.scene->textures.push_back(checker);
    b.scene->materials[green].texture = 0;
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    // Along the x axis the ball's surface at x = 1 is gone: the cube's face at x = 0.5, flipped.
    SurfaceHit hit = trace(scene, {5, 0.1f, 0.05f}, {-1, 0, 0});
    EXPECT_NEAR(hit.position.x, 0.5f, 1e-5f);
    EXPECT_NEAR(hit.normal.x, 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, green);
    EXPECT_EQ(hit.shape_kind, -1);
    EXPECT_NEAR(hit.object_position.x, -0.5f, 1e-5f);  // in the mesh's own space
    // Above the bite, the ball is still there.
    hit = trace(scene, {0, 5, 0}, {0, -1, 0});
    EXPECT_NEAR(hit.position.y, 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, grey);
    // From inside the bite (outside the solid) looking back along +x: nothing.
    EXPECT_TRUE(misses(scene, {0.7f, 0.1f, 0.05f}, {1, 0, 0}));
    // The mesh in an intersection, with the ray starting inside both.
    JobBuilder c(8, 8);
    c.scene->materials = b.scene->materials;
    c.scene->meshes = b.scene->meshes;
    const int ball2 = sphere_at(c, {0, 0, 0}, 1.0, grey);
    const int box2 = operand(c, NodeKind::mesh, green);
    c.scene->nodes[box2].mesh = 0;
    c.scale(box2, {3, 3, 3});  // [-1.5, 1.5]^3 contains the ball
    csg(c, NodeKind::csg_intersection, box2, ball2);
    const RenderScene scene2(*c.scene, flatten_scene(*c.scene, 0, false));
    hit = trace(scene2, {0, 0, 0}, {0, 0, 1}, 1e-4f);
    EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, grey);
}

TEST(CsgScene, NestedInstancedAndTransformedAtEveryLevel) {
    JobBuilder b(8, 8);
    const int red_m = b.material({1, 0, 0}), blue_m = b.material({0, 0, 1});
    // ((cube - sphere) u small cube), used twice, moved by its parents.
    const int cube = operand(b, NodeKind::cube);
    const int bite = sphere_at(b, {0, 0, 1}, 0.5, blue_m);  // hollows the +z face's centre
    const int diff = csg(b, NodeKind::csg_difference, cube, bite, -1);
    const int knob = operand(b, NodeKind::cube);
    b.translate(knob, {0, 1.25, 0});
    b.scale(knob, {0.25, 0.25, 0.25});  // sits on top: y in [1, 1.5]
    const int piece = csg(b, NodeKind::csg_union, diff, knob, -1, red_m);  // the material inherits
    b.scale(piece, {2, 2, 2});
    const int g1 = b.add(NodeKind::group, -1), g2 = b.add(NodeKind::group, -1);
    b.translate(g1, {-10, 0, 0});
    b.translate(g2, {10, 0, 0});
    b.scene->nodes[g1].children.push_back(piece);
    b.scene->nodes[g2].children.push_back(piece);
    const FlatScene flat = flatten_scene(*b.scene, 0, false);
    ASSERT_EQ(flat.csg_objects.size(), 2u);
    const RenderScene scene(*b.scene, flat);
    for (float x : {-10.0f, 10.0f}) {
        // Straight at the bitten face: the bite's bottom at z = 2 * (1 - 0.5) = 1.
        SurfaceHit hit = trace(scene, {x, 0, 10}, {0, 0, -1});
        EXPECT_NEAR(hit.position.z, 1.0f, 1e-5f);
        EXPECT_EQ(hit.material, blue_m);
        EXPECT_NEAR(hit.normal.z, 1.0f, 1e-5f);
        // Beside the bite: the cube's face at z = 2.
        hit = trace(scene, {x + 1.5f, 1.5f, 10}, {0, 0, -1});
        EXPECT_NEAR(hit.position.z, 2.0f, 1e-5f);
        EXPECT_EQ(hit.material, red_m);
        // From above: the knob's top at y = 3.
        hit = trace(scene, {x, 10, 0}, {0, -1, 0});
        EXPECT_NEAR(hit.position.y, 3.0f, 1e-5f);
        EXPECT_EQ(hit.material, red_m);
    }
    EXPECT_TRUE(misses(scene, {0, 10, 0}, {0, -1, 0}));
}

TEST(CsgScene, MalformedCsgIsAnError) {
    JobBuilder b(8, 8);
    const int s = operand(b, NodeKind::sphere);
    csg(b, NodeKind::csg_union, s, -1);
    EXPECT_THROW(flatten_scene(*b.scene, 0, false), InputError);
    JobBuilder c(8, 8);
    const int t = operand(c, NodeKind::sphere);
    const int u = csg(c, NodeKind::csg_union, t, t);
    c.scene->nodes[u].csg_right = u;  // contains itself
    EXPECT_THROW(flatten_scene(*c.scene, 0, false), InputError);
}

TEST(CsgScene, ShippedScenesBuildTheirCsgObjects) {
    // csg_lens: one lens; csg_showcase: union, die, drilled die, cup, glass of juice, paperweight.
    for (const auto& [name, objects] : {std::pair{"csg_lens.lua", 1u}, std::pair{"csg_showcase.lua", 6u}}) {
        const SceneScript script = load_scene_script(std::string(CAUSTICA_SOURCE_DIR "/scenes/") + name);
        ASSERT_EQ(script.renders.size(), 1u) << name;
        const RenderJob& job = script.renders[0];
        const FlatScene flat = flatten_scene(job);
        EXPECT_EQ(flat.csg_objects.size(), objects) << name;
        const RenderScene scene(*job.scene, flat);
        EXPECT_EQ(scene.info().csg_objects, objects) << name;
        // The camera's central ray meets the scene.
        const Camera camera(job.camera, job.width, job.height);
        SurfaceHit hit;
        EXPECT_TRUE(scene.intersect(camera.generate(0.5f * job.width, 0.5f * job.height), hit)) << name;
    }
}

// ---- renders ----

namespace {

/// Renders one sample per pixel through our own RenderScene (so the CSG box setting can be chosen).
Image render_direct(const RenderJob& job, bool csg_boxes) {
    FlatScene flat = flatten_scene(job);
    flat.csg_bounding_boxes = csg_boxes;
    const RenderScene scene(*job.scene, flat);
    ShadingSetup setup;
    setup.scene = &scene;
    for (int index : job.lights) {
        const LightDesc& d = job.scene->lights[index];
        setup.lights.push_back({glm::vec3(d.position), glm::vec3(d.colour), glm::vec3(d.falloff), float(d.radius)});
    }
    setup.ambient = glm::vec3(job.ambient);
    setup.miss_colour = glm::vec3(job.miss_colour);
    const Integrator integrator(setup);
    const Camera camera(job.camera, job.width, job.height);
    TileContext context;
    context.integrator = &integrator;
    context.camera = &camera;
    Image image(job.width, job.height);
    RayCounters counters;
    for (const Tile& tile : make_tiles(job.width, job.height, tile_size))
        render_first_pass_tile(context, tile, image, counters);
    return image;
}

void expect_identical(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    int differing = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (a.at(x, y) != b.at(x, y) && ++differing <= 3) ADD_FAILURE() << "pixel " << x << "," << y << " differs";
    EXPECT_EQ(differing, 0);
}

/// A lit floor for the renders to cast shadows on.
void add_floor(JobBuilder& b) {
    const int floor = b.add(NodeKind::cube, b.material({0.7, 0.7, 0.6}));
    b.translate(floor, {0, -1.6, 0});
    b.scale(floor, {5, 0.1, 5});
}

}  // namespace

TEST(CsgInvariance, DifferenceThatRemovesEverythingRendersNothing) {
    JobBuilder b(40, 40);
    const int inner = operand(b, NodeKind::cube, b.material({1, 0, 0}));
    const int outer = sphere_at(b, {0, 0, 0}, 2.0, b.material({0, 1, 0}));  // contains the cube
    b.rotate(inner, 1, 30);
    csg(b, NodeKind::csg_difference, inner, outer);
    b.camera({0, 1, 6}, {0, -1, -6}, 40);
    b.light({3, 5, 5}, {1, 1, 1});
    b.job.ambient = {0.2, 0.2, 0.2};
    b.job.miss_colour = {0.1, 0.2, 0.3};
    b.job.options.disable_aa = true;
    const Image image = caustica::testing::render(b.build());
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) ASSERT_EQ(image.at(x, y), glm::vec3(0.1f, 0.2f, 0.3f)) << x << "," << y;
}

TEST(CsgInvariance, IntersectionWithAContainingBoxRendersAsTheObjectAlone) {
    auto build = [](bool with_box) {
        JobBuilder b(48, 48);
        add_floor(b);
        const int ball = sphere_at(b, {0.2, -0.3, 0.1}, 1.1, b.material({0.9, 0.5, 0.2}, {0.4, 0.4, 0.4}, 25));
        b.scale(ball, {1.0, 0.8, 1.0});
        if (with_box) {
            const int box = operand(b, NodeKind::cube, b.material({0, 1, 0}));
            b.scale(box, {3, 3, 3});
            csg(b, NodeKind::csg_intersection, ball, box);
        } else {
            b.scene->nodes[0].children.push_back(ball);
        }
        b.camera({0, 1.5, 6}, {0, -1.5, -6}, 45);
        b.light({3, 6, 4}, {1, 1, 1});
        b.job.ambient = {0.2, 0.2, 0.2};
        b.job.miss_colour = {0.1, 0.1, 0.2};
        b.job.options.disable_aa = true;
        return caustica::testing::render(b.build());
    };
    // Same interval from the same shape code and matrices: the images agree bit for bit.
    expect_identical(build(true), build(false));
}

TEST(CsgInvariance, BoundingBoxesDoNotChangeTheImage) {
    JobBuilder b(64, 64);
    add_floor(b);
    const int glass_m = dielectric(b, {0.9, 0.95, 1.0}, 1.5);
    // A slab with a grid of holes (spheres and cylinders), nested unions, and a glass lens.
    const int slab = operand(b, NodeKind::cube, b.material({0.3, 0.6, 0.9}));
    b.scale(slab, {1.5, 1.0, 0.2});
    const int holes = operand(b, NodeKind::group, b.material({0.9, 0.9, 0.2}));
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 4; ++j) {
            const bool ball = (i + j) % 2 == 0;
            const int h = operand(b, ball ? NodeKind::sphere : NodeKind::cylinder);
            b.translate(h, {-1.2 + 0.6 * i, -0.75 + 0.5 * j, 0});
            if (ball) b.scale(h, {0.22, 0.22, 0.22});
            else {
                b.rotate(h, 0, 90);
                b.scale(h, {0.15, 0.5, 0.15});
            }
            b.scene->nodes[holes].children.push_back(h);
        }
    const int plate = csg(b, NodeKind::csg_difference, slab, holes);
    b.translate(plate, {0, 0, -0.8});
    const int back = sphere_at(b, {0, 0, 0.6}, 1.0, glass_m), front = sphere_at(b, {0, 0, -0.6}, 1.0, glass_m);
    const int lens = csg(b, NodeKind::csg_intersection, back, front);
    b.translate(lens, {0.4, 0.1, 1.0});
    b.scale(lens, {0.7, 0.7, 0.7});
    b.camera({0.5, 0.8, 5}, {-0.1, -0.15, -1}, 45);
    b.light({2, 4, 5}, {1, 1, 1});
    b.job.ambient = {0.2, 0.2, 0.2};
    b.job.miss_colour = {0.05, 0.05, 0.1};
    const RenderJob job = b.build();
    const Image with_boxes = render_direct(job, true), without = render_direct(job, false);
    expect_identical(with_boxes, without);
    // The picture is not empty: the plate and the lens are in it.
    int background = 0;
    for (int y = 0; y < with_boxes.height; ++y)
        for (int x = 0; x < with_boxes.width; ++x) background += with_boxes.at(x, y) == glm::vec3(0.05f, 0.05f, 0.1f);
    EXPECT_LT(background, with_boxes.width * with_boxes.height / 2);
    // Through the render session with the option as well.
    RenderJob off = job;
    off.options.disable_csg_bb = true;
    off.options.disable_aa = true;
    RenderJob on = job;
    on.options.disable_aa = true;
    expect_identical(caustica::testing::render(on), caustica::testing::render(off));
}
