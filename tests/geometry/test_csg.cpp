// Constructive solid geometry: the interval algebra on hand-made lists and CSG objects traced
// through the Embree scene against analytic answers. Media, materials and renders:
// test_csg_media.cpp.
#include "core/geometry/csg_intervals.h"
#include "core/geometry/render_scene.h"
#include "core/lua/scene_loader.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "tests/geometry/test_csg_support.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace caustica;
using namespace caustica::csg_testing;

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
