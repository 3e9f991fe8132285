// CSG media and materials (docs/SCENE_LANGUAGE.md, "CSG media"): the interfaces a union records,
// the material and medium of surfaces a difference carves, which hits are on CSG objects; and
// renders of CSG objects (invariances). The interval algebra and geometry: test_csg.cpp.
#include "core/geometry/csg_intervals.h"
#include "core/geometry/render_scene.h"
#include "core/integrators/progressive.h"
#include "core/render/tile_renderer.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "tests/geometry/test_csg_support.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace caustica;
using namespace caustica::csg_testing;

// ---- interfaces of unions, on hand-made interval lists ----

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

TEST(CsgIntervals, DifferenceMarksTheSurfacesItCarves) {
    // A = [0, 10] minus B = [3, 5]: the two ends B exposes are carved, with B's material; the
    // segments' medium stays A's (CsgTree decides what is behind a carved surface).
    const CsgSegmentList a = list({segment(0, 10, red, 0)}), b = list({segment(3, 5, glass, 1)});
    const CsgSegmentList d = subtract(a, b);
    ASSERT_EQ(d.size(), 2);
    expect_segment(d[0], 0, 3, red, red, glass);
    expect_segment(d[1], 5, 10, red, glass, red);
    EXPECT_FALSE(d[0].enter.carved);
    EXPECT_TRUE(d[0].leave.carved);
    EXPECT_TRUE(d[1].enter.carved);
    EXPECT_FALSE(d[1].leave.carved);
    expect_boundary(d, 1, 3, glass, red, -1);
    // A - (B - C), C = [3.5, 4.5]: C's surfaces are flipped twice (they bound A again) and stay
    // carved: they still belong to a subtracted operand.
    const CsgSegmentList nested = subtract(a, subtract(b, list({segment(3.5f, 4.5f, liquid, 2)})));
    ASSERT_EQ(nested.size(), 3);
    expect_segment(nested[1], 3.5f, 4.5f, red, liquid, liquid);
    EXPECT_TRUE(nested[1].enter.carved);
    EXPECT_TRUE(nested[1].leave.carved);
    EXPECT_EQ(nested[1].enter.normal.x, -1.0f);  // an entry again: against the ray
    // The marks survive a further operation.
    const CsgSegmentList u = unite(d, list({segment(20, 21, red, 3)}));
    ASSERT_EQ(u.size(), 3);
    EXPECT_TRUE(u[0].leave.carved);
    EXPECT_TRUE(u[1].enter.carved);
    EXPECT_FALSE(u[2].enter.carved);
}

// ---- media of CSG objects in the Embree scene ----

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

namespace {

/// A cube [-1,1]^3 of material `cube_m` minus a ball of material `ball_m`, radius 0.5, centred
/// on the +z face: the hollow's bottom is at z = 0.5 on the axis.
RenderScene cube_minus_ball(JobBuilder& b, int cube_m, int ball_m) {
    const int cube = operand(b, NodeKind::cube, cube_m);
    const int ball = sphere_at(b, {0, 0, 1}, 0.5, ball_m);
    csg(b, NodeKind::csg_difference, cube, ball);
    return RenderScene(*b.scene, flatten_scene(*b.scene, 0, false));
}

}  // namespace

TEST(CsgScene, DifferenceShadesTheCarvedHollowWithTheSubtractedMaterial) {
    JobBuilder b(8, 8);
    const int red_m = b.material({1, 0, 0}), green_m = b.material({0, 1, 0});
    const RenderScene scene = cube_minus_ball(b, red_m, green_m);
    // On the axis: the hollow's bottom, the ball's surface seen from outside the ball.
    SurfaceHit hit = trace(scene, {0, 0, 5}, {0, 0, -1});
    EXPECT_NEAR(hit.position.z, 0.5f, 1e-5f);
    EXPECT_NEAR(hit.normal.z, 1.0f, 1e-6f);  // out of the solid, into the hollow
    EXPECT_EQ(hit.material, green_m);
    EXPECT_TRUE(hit.in_csg);
    // An opaque ball lets no path through: the solid behind its surface is still the cube's.
    EXPECT_EQ(hit.medium_inside, red_m);
    EXPECT_EQ(hit.medium_outside, -1);
    // Off the axis at x = 0.3: z = 1 - sqrt(0.25 - 0.09) = 0.6, normal towards the ball's centre.
    hit = trace(scene, {0.3f, 0, 5}, {0, 0, -1});
    EXPECT_NEAR(hit.position.z, 0.6f, 1e-5f);
    EXPECT_NEAR(glm::dot(hit.normal, glm::vec3(-0.6f, 0.0f, 0.8f)), 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, green_m);
    // Beside the hollow: the cube's own top face.
    hit = trace(scene, {0.8f, 0, 5}, {0, 0, -1});
    EXPECT_NEAR(hit.position.z, 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, red_m);
    EXPECT_EQ(hit.medium_inside, red_m);
}

TEST(CsgScene, TransparentSubtractedOperandIsTheMediumBehindTheCarvedSurface) {
    // The path that re-enters A - B through B's surface is tinted by B.
    JobBuilder b(8, 8);
    const int glass_m = dielectric(b, {0, 0, 0}, 1.5), green_m = dielectric(b, {0, 0.5, 0}, 1.33);
    const RenderScene scene = cube_minus_ball(b, glass_m, green_m);
    SurfaceHit hit = trace(scene, {0, 0, 5}, {0, 0, -1});
    EXPECT_NEAR(hit.position.z, 0.5f, 1e-5f);
    EXPECT_EQ(hit.material, green_m);
    EXPECT_EQ(hit.medium_inside, green_m);
    EXPECT_EQ(hit.medium_outside, -1);
    // Onwards through the solid: the cube's bottom face, its own material on both counts.
    hit = trace(scene, hit.position, {0, 0, -1}, scene.epsilon());
    EXPECT_NEAR(hit.position.z, -1.0f, 1e-5f);
    EXPECT_NEAR(hit.normal.z, -1.0f, 1e-6f);
    EXPECT_EQ(hit.material, glass_m);
    EXPECT_EQ(hit.medium_inside, glass_m);
    // From inside the solid the same surface is met leaving it (normal along the ray).
    hit = trace(scene, {0, 0, 0}, {0, 0, 1}, scene.epsilon());
    EXPECT_NEAR(hit.position.z, 0.5f, 1e-5f);
    EXPECT_NEAR(hit.normal.z, 1.0f, 1e-6f);
    EXPECT_EQ(hit.material, green_m);
    EXPECT_EQ(hit.medium_inside, green_m);
    // The cube's own top face beside the hollow is untouched.
    hit = trace(scene, {0.8f, 0, 5}, {0, 0, -1});
    EXPECT_EQ(hit.material, glass_m);
    EXPECT_EQ(hit.medium_inside, glass_m);
    // The rule looks at B's material only: a transparent ball carved from an opaque cube.
    JobBuilder c(8, 8);
    const int red_m = c.material({1, 0, 0}), clear_m = dielectric(c, {0, 0, 0}, 1.33);
    const RenderScene opaque = cube_minus_ball(c, red_m, clear_m);
    hit = trace(opaque, {0, 0, 5}, {0, 0, -1});
    EXPECT_EQ(hit.material, clear_m);
    EXPECT_EQ(hit.medium_inside, clear_m);
}

TEST(CsgScene, HitsOnCsgObjectsAreMarkedOnEveryQueryPath) {
    EXPECT_FALSE(SurfaceHit{}.in_csg);
    JobBuilder b(8, 8);
    const int m = b.material({0.5, 0.5, 0.5});
    const int plain = sphere_at(b, {-3, 0, 0}, 1.0, m);  // an ordinary sphere
    b.scene->nodes[0].children.push_back(plain);
    const int left = sphere_at(b, {2.5, 0, 0}, 1.0, m), right = sphere_at(b, {3.5, 0, 0}, 1.0, m);
    csg(b, NodeKind::csg_union, left, right);  // a CSG object around x = 3
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    ASSERT_EQ(scene.info().csg_objects, 1u);
    // One ray at a time, reusing one SurfaceHit: the mark follows the object hit.
    SurfaceHit hit;
    for (float x : {3.0f, -3.0f, 3.0f, -3.0f}) {
        ASSERT_TRUE(scene.intersect(Ray{{x, 0, 5}, {0, 0, -1}, 0.0f, ray_infinity}, hit));
        EXPECT_NEAR(hit.position.z, x > 0.0f ? std::sqrt(0.75f) : 1.0f, 1e-5f);  // the union's crest, the sphere's top
        EXPECT_EQ(hit.in_csg, x > 0.0f) << x;
    }
    // Packets of 8, the answers pre-set to the wrong value; lane 5 is off.
    Ray rays[8];
    int valid[8];
    SurfaceHit hits[8];
    bool found[8];
    for (int i = 0; i < 8; ++i) {
        const float x = i % 2 == 0 ? 3.0f : -3.0f;
        rays[i] = Ray{{x, 0.1f * static_cast<float>(i) - 0.35f, 5}, {0, 0, -1}, 0.0f, ray_infinity};
        valid[i] = i != 5;
        hits[i].in_csg = i % 2 != 0;
    }
    scene.intersect8(rays, valid, hits, found);
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(found[i], i != 5) << i;
        if (!found[i]) continue;
        EXPECT_EQ(hits[i].in_csg, i % 2 == 0) << i;
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
    const ProgressiveIntegrator integrator(setup);
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
