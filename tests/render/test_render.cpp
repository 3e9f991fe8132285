// End-to-end renders of hand-built scenes with answers known in closed form.
#include "core/scene/camera.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/source_location.h"
#include "tests/scene_test_helpers.h"
#include "tests/test_support.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

/// A unit sphere at the origin seen from z = 5 with a light at the eye.
JobBuilder lit_sphere(glm::dvec3 kd, glm::dvec3 ks = glm::dvec3(0.0), double shininess = 0.0) {
    JobBuilder b(65, 65);  // odd: the centre pixel's ray is exactly the axis
    b.add(NodeKind::sphere, b.material(kd, ks, shininess));
    b.camera({0, 0, 5}, {0, 0, -1}, 30);
    b.light({0, 0, 5}, {1, 1, 1});
    b.job.options.disable_aa = true;
    return b;
}

}  // namespace

TEST(Render, LambertAtNormalIncidenceIsKd) {
    JobBuilder b = lit_sphere({0.5, 0.25, 0.125});
    const Image image = caustica::testing::render(b.build());
    const glm::vec3 c = image.at(32, 32);
    EXPECT_NEAR(c.x, 0.5f, 1e-4f);
    EXPECT_NEAR(c.y, 0.25f, 1e-4f);
    EXPECT_NEAR(c.z, 0.125f, 1e-4f);
    EXPECT_EQ(image.at(0, 0), glm::vec3(1.0f));  // the miss colour: the default is white
}

TEST(Render, AmbientAddsAmbientTimesKd) {
    JobBuilder b = lit_sphere({0.5, 0.5, 0.5});
    b.job.ambient = {0.2, 0.4, 0.0};
    const glm::vec3 c = caustica::testing::render(b.build()).at(32, 32);
    EXPECT_NEAR(c.x, 0.5f + 0.1f, 1e-4f);
    EXPECT_NEAR(c.y, 0.5f + 0.2f, 1e-4f);
    EXPECT_NEAR(c.z, 0.5f, 1e-4f);
}

TEST(Render, QuadraticFalloffDividesByDistanceSquared) {
    JobBuilder b = lit_sphere({1, 1, 1});
    b.scene->lights[0].falloff = {0.0, 0.0, 1.0};
    // The sphere's front point is 4 units from the light at the eye.
    EXPECT_NEAR(caustica::testing::render(b.build()).at(32, 32).x, 1.0f / 16.0f, 1e-5f);
    b.scene->lights[0].falloff = {1.0, 0.5, 0.0};
    EXPECT_NEAR(caustica::testing::render(b.build()).at(32, 32).x, 1.0f / 3.0f, 1e-5f);
}

TEST(Render, PhongHighlightAtTheMirrorDirection) {
    // Light at the eye: r == v at the centre, so the highlight adds exactly ks.
    JobBuilder b = lit_sphere({0.25, 0.25, 0.25}, {0.5, 0.5, 0.5}, 20);
    EXPECT_NEAR(caustica::testing::render(b.build()).at(32, 32).x, 0.75f, 1e-4f);
}

TEST(Render, HardShadowBlocksTheLight) {
    JobBuilder b(33, 33);
    const int floor_material = b.material({1, 1, 1});
    const int floor = b.add(NodeKind::cube, floor_material);
    b.translate(floor, {0, -1.1, 0});
    b.scale(floor, {10, 0.1, 10});  // M = T * S: a slab y in [-1.2, -1.0]
    const int blocker = b.add(NodeKind::sphere, b.material({0, 0, 0}));
    b.scale(blocker, {0.5, 0.5, 0.5});
    b.light({0, 10, 0}, {1, 1, 1});
    b.camera({0, 5, 5}, {0, -5, -5}, 60);
    b.job.options.disable_aa = true;
    const RenderJob job = b.build();
    const Image image = caustica::testing::render(job);
    // Floor point straight below the blocker is in shadow; a point 3 units to the side is lit.
    const Camera camera(job.camera, job.width, job.height);
    glm::vec2 shadowed, lit;
    ASSERT_TRUE(camera.project({0.3f, -1.0f, 0.3f}, shadowed));  // inside the ~0.55-radius shadow disc
    ASSERT_TRUE(camera.project({3, -1.0f, 0}, lit));
    EXPECT_EQ(image.at(int(shadowed.x), int(shadowed.y)), glm::vec3(0.0f));
    EXPECT_GT(image.at(int(lit.x), int(lit.y)).x, 0.5f);
}

TEST(Render, MirrorReflectsWithKs) {
    // Ambient light only: the black mirror shows ks times the ambient colour of the ball behind the eye.
    JobBuilder b(33, 33);
    const int mirror = b.add(NodeKind::cube, b.material({0, 0, 0}, {0.5, 0.25, 0.5}, 10, true));
    b.scale(mirror, {5, 5, 0.1});
    const int ball = b.add(NodeKind::sphere, b.material({0.8, 0.8, 0.4}));
    b.translate(ball, {0, 0, 20});
    b.job.ambient = {1, 1, 1};
    b.camera({0, 0, 5}, {0, 0, -1}, 20);
    b.job.options.disable_aa = true;
    const Image image = caustica::testing::render(b.build());
    EXPECT_NEAR(image.at(16, 16).x, 0.4f, 1e-5f);
    EXPECT_NEAR(image.at(16, 16).y, 0.2f, 1e-5f);
    EXPECT_NEAR(image.at(16, 16).z, 0.2f, 1e-5f);
    // --max-depth bounds the progressive integrator's recursion (the classic one has no such
    // option: it cuts by weight and returns white past depth 15; docs/CAUSTICS.md).
    b.job.options.integrator = IntegratorKind::progressive;
    EXPECT_NEAR(caustica::testing::render(b.build()).at(16, 16).x, 0.4f, 1e-5f);
    b.job.options.max_depth = 0;  // no reflection at all
    EXPECT_EQ(caustica::testing::render(b.build()).at(16, 16), glm::vec3(0.0f));
}

TEST(Render, ReproducibleOutputIsIdenticalForOneAndTwoThreads) {
    JobBuilder b(80, 60);
    const int m = b.material({0.7, 0.3, 0.2}, {0.4, 0.4, 0.4}, 30);
    for (int i = 0; i < 5; ++i) {
        const int s = b.add(i % 2 ? NodeKind::cube : NodeKind::sphere, m);
        b.translate(s, {i - 2.0, 0.3 * i, -i});
        b.scale(s, {0.4, 0.4, 0.4});
    }
    b.light({3, 4, 5}, {1, 1, 1});
    b.camera({0, 0, 6}, {0, 0, -1}, 50);
    b.job.options.aa_threshold = 0.05;  // many anti-aliased pixels: exercises the random streams
    // The progressive integrator's jittered samples draw on the random streams; the classic grid
    // has none, but must be just as independent of the thread count.
    for (const IntegratorKind kind : {IntegratorKind::progressive, IntegratorKind::classic}) {
        b.job.options.integrator = kind;
        b.job.options.threads = 1;
        const Image one = caustica::testing::render(b.build());
        b.job.options.threads = 2;
        const Image two = caustica::testing::render(b.build());
        ASSERT_EQ(one.pixels.size(), two.pixels.size());
        for (std::size_t i = 0; i < one.pixels.size(); ++i) ASSERT_EQ(one.pixels[i], two.pixels[i]) << i;
    }
}

// Any thread count, not only 1 and 2: with 3 and 7 threads (more than the cores of most machines
// that run this, so tiles, photon blocks and tree builds are handed out in other orders) the bits
// are one thread's, for classic with caustic and GI photons and anti-aliasing, and for progressive
// passes with GI and a radius per pixel (factors updated before pass 8).
TEST(Render, ReproducibleForOneThreeAndSevenThreads) {
    const RenderJob scene = caustica::testing::glass_and_mirror_balls_job();
    for (const IntegratorKind kind : {IntegratorKind::classic, IntegratorKind::progressive}) {
        RenderJob job = scene;
        job.options.integrator = kind;
        job.options.reproducible = true;
        job.options.caustic_num_photons = 40'000;
        job.options.gi = true;
        job.options.gi_num_photons = 40'000;
        if (kind == IntegratorKind::progressive) {
            job.options.passes = 9;
            job.options.adaptive_radius = true;
        }
        job.options.threads = 1;
        const Image one = caustica::testing::render(job);
        double sum = 0.0;
        for (const glm::vec3& p : one.pixels) sum += p.x + p.y + p.z;
        ASSERT_GT(sum / (3.0 * static_cast<double>(one.pixels.size())), 0.05);  // a lit image
        for (int threads : {3, 7}) {
            job.options.threads = threads;
            const Image many = caustica::testing::render(job);
            ASSERT_EQ(one.pixels.size(), many.pixels.size());
            std::size_t differing = 0;
            for (std::size_t i = 0; i < one.pixels.size(); ++i) differing += one.pixels[i] != many.pixels[i];
            EXPECT_EQ(differing, 0u) << (kind == IntegratorKind::classic ? "classic, " : "progressive, ") << threads
                                     << " threads against 1";
        }
    }
}


// The balanced radius scales the sequence from the estimate, whose sums are the same bits for any
// thread count: so are the images.
TEST(Render, BalancedRadiusIsReproducibleForOneAndThreeThreads) {
    RenderJob job = caustica::testing::glass_and_mirror_balls_job();
    job.options.integrator = IntegratorKind::progressive;
    job.options.reproducible = true;
    job.options.caustic_num_photons = 40'000;
    job.options.passes = 17;  // scaled before passes 4, 8 and 16
    job.options.auto_radius = true;
    job.options.threads = 1;
    const Image one = caustica::testing::render(job);
    job.options.threads = 3;
    const Image three = caustica::testing::render(job);
    ASSERT_EQ(one.pixels.size(), three.pixels.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < one.pixels.size(); ++i) differing += one.pixels[i] != three.pixels[i];
    EXPECT_EQ(differing, 0u);
}
TEST(Render, AntialiasingTouchesOnlyEdges) {
    JobBuilder b = lit_sphere({1, 1, 1});
    b.job.options.disable_aa = false;
    b.job.options.draw_aa = true;
    const Image image = caustica::testing::render(b.build());
    // Centre: not an edge, so not marked. Classic anti-aliasing (the default, aa grid 3): an
    // unrefined pixel is the mean of its 4 corner samples at (i + 1/2)/3, i = 0, 2: each a third of
    // a pixel from the axis on both image axes. With the light at the eye, each sample is
    // n.l = -n.d at its hit.
    const double tan_half = std::tan(15.0 * 3.14159265358979323846 / 180.0);  // 30 degrees across
    const double a = (2.0 / 3.0) / 65.0 * tan_half;  // a third of a pixel, on the plane at distance 1
    const glm::dvec3 d = glm::normalize(glm::dvec3(a, a, -1.0));
    const glm::dvec3 eye(0, 0, 5);
    const double b_half = glm::dot(eye, d), t = -b_half - std::sqrt(b_half * b_half - (glm::dot(eye, eye) - 1.0));
    const double corner = -glm::dot(eye + t * d, d);  // the same at all four corners, by symmetry
    EXPECT_LT(corner, 1.0);
    EXPECT_NEAR(image.at(32, 32).x, corner, 1e-5);
    EXPECT_EQ(image.at(32, 32), glm::vec3(image.at(32, 32).x));  // grey: not painted red
    EXPECT_EQ(image.at(0, 0), glm::vec3(1.0f));  // background (white miss colour): not an edge
    int marked = 0;
    for (int x = 0; x < 65; ++x) marked += image.at(x, 32) == glm::vec3(1, 0, 0);
    EXPECT_GE(marked, 2);  // the silhouette crosses the middle row twice
    EXPECT_LE(marked, 8);
}

TEST(Render, CancelStopsPromptlyAndReportsIt) {
    JobBuilder b(1024, 1024);
    b.add(NodeKind::sphere, b.material({1, 1, 1}));
    b.camera({0, 0, 5}, {0, 0, -1}, 30);
    b.light({0, 0, 5}, {1, 1, 1});
    RenderSession session;
    session.set_job(b.build());
    session.start();
    session.cancel();
    EXPECT_FALSE(session.wait());
    EXPECT_TRUE(session.progress().cancelled);
}

// The command line's progress loop waits on wait_for_end rather than sleeping: a render still
// running is not ended when the wait times out, and the wait returns as the render ends (a cancel
// from another thread here), long before its own timeout.
TEST(Render, WaitForEndReturnsAsTheRenderEnds) {
    JobBuilder b = lit_sphere({1, 1, 1});
    RenderJob job = b.build();
    job.options.integrator = IntegratorKind::progressive;
    job.options.time_limit = 1e6;  // passes until cancelled
    RenderSession session;
    session.set_job(job);
    EXPECT_TRUE(session.wait_for_end(0.0));  // nothing running yet
    session.start();
    EXPECT_FALSE(session.wait_for_end(0.05));
    const auto start = std::chrono::steady_clock::now();
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        session.cancel();
    });
    EXPECT_TRUE(session.wait_for_end(600.0));
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    canceller.join();
    EXPECT_LT(waited, caustica::testing::time_bound(5.0));
    EXPECT_FALSE(session.wait());
    EXPECT_TRUE(session.progress().cancelled);
}

TEST(Render, CameraMoveReusesTheBvh) {
    JobBuilder b = lit_sphere({1, 1, 1});
    RenderSession session;
    RenderJob job = b.build();
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    job.camera.eye = {1, 0, 5};
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    EXPECT_EQ(session.stage_counters().scene_builds, 1);
    EXPECT_EQ(session.stage_counters().renders, 2);
    b.translate(1, {0.5, 0, 0});  // geometry change
    session.set_job(b.build());
    session.start();
    ASSERT_TRUE(session.wait());
    EXPECT_EQ(session.stage_counters().scene_builds, 2);
}

TEST(Transforms, SeedConventionPostMultipliesCourseConventionPreMultiplies) {
    std::vector<TransformOp> ops(2);
    ops[0].kind = TransformOp::Kind::translate;
    ops[0].amount = {1, 0, 0};
    ops[1].kind = TransformOp::Kind::scale;
    ops[1].amount = {2, 2, 2};
    const glm::dvec4 origin(0, 0, 0, 1);
    // The original's: M = T * S, the last call (scale) acts first: the origin goes to (1,0,0).
    EXPECT_EQ(glm::dvec3(compose_transforms(ops, false) * origin), glm::dvec3(1, 0, 0));
    // Course: M = S * T, calls act in order: translate then scale: (2,0,0).
    EXPECT_EQ(glm::dvec3(compose_transforms(ops, true) * origin), glm::dvec3(2, 0, 0));
}

TEST(Transforms, CourseCubeIsTheUnitCubeSeedCubeIsCentred) {
    JobBuilder b(8, 8);
    b.add(NodeKind::cube, -1);
    FlatScene seed = flatten_scene(*b.scene, 0, false);
    FlatScene course = flatten_scene(*b.scene, 0, true);
    EXPECT_EQ(seed.primitives[0].shape.a, glm::vec3(-1));
    EXPECT_EQ(course.primitives[0].shape.a, glm::vec3(0));
    EXPECT_EQ(course.primitives[0].shape.b, glm::vec3(1));
    EXPECT_EQ(seed.warnings.size(), 1u);  // no material
}

TEST(Transforms, SingularWorldTransformNamesTheNode) {
    JobBuilder b(8, 8);
    const int n = b.add(NodeKind::sphere, -1);
    b.scene->nodes[n].where = {"scene.lua", 7};
    b.scale(n, {1, 1e-300, 1});
    try {
        flatten_scene(*b.scene, 0, false);
        FAIL() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "scene.lua:7: node 'node1': its world transform is singular or not finite");
    }
}

TEST(Render, DisableBvGivesTheSameImage) {
    JobBuilder b(40, 30);
    const int m = b.material({0.7, 0.3, 0.2}, {0.4, 0.4, 0.4}, 30, true);
    for (int i = 0; i < 12; ++i) {
        const int s = b.add(i % 3 == 0 ? NodeKind::cube : i % 3 == 1 ? NodeKind::sphere : NodeKind::cone, m);
        b.translate(s, {i % 4 - 1.5, i / 4 - 1.0, -0.3 * i});
        b.scale(s, {0.35, 0.35, 0.35});
    }
    b.light({3, 4, 5}, {1, 1, 1});
    b.camera({0, 0, 6}, {0, 0, -1}, 50);
    const Image with_bv = caustica::testing::render(b.build());
    b.job.options.disable_bv = true;
    const Image without = caustica::testing::render(b.build());
    for (std::size_t i = 0; i < with_bv.pixels.size(); ++i) ASSERT_EQ(with_bv.pixels[i], without.pixels[i]) << i;
}
