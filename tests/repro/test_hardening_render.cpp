// The renderer under hostile but finite input (docs/RELIABILITY.md): deep nesting, far and huge
// values, option values that would allocate without bound, malformed OBJ files, hashing and the
// denormal mode. Each test fails (or crashes) without the change it backs.
#include "core/util/denormals.h"
#include "core/geometry/mesh_obj.h"
#include "core/scene/options.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/scene_validate.h"
#include "core/scene/source_location.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <pthread.h>

#include <cmath>
#include <exception>
#include <functional>
#include <string>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

/// Runs `body` on a thread with a stack of `bytes` (far below the default 8 MiB), so that any
/// recursion proportional to the input's depth overflows it. Rethrows what `body` threw.
void run_with_small_stack(std::size_t bytes, const std::function<void()>& body) {
    struct Call {
        const std::function<void()>* body;
        std::exception_ptr error;
    } call{&body, nullptr};
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, bytes);
    pthread_t thread;
    const int started = pthread_create(
        &thread, &attr,
        [](void* p) -> void* {
            auto* c = static_cast<Call*>(p);
            try {
                (*c->body)();
            } catch (...) {
                c->error = std::current_exception();
            }
            return nullptr;
        },
        &call);
    pthread_attr_destroy(&attr);
    ASSERT_EQ(started, 0);
    pthread_join(thread, nullptr);
    if (call.error) std::rethrow_exception(call.error);
}

std::size_t non_finite_pixels(const Image& image) {
    std::size_t bad = 0;
    for (const glm::vec3& p : image.pixels) bad += !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    return bad;
}

/// The message of the InputError `body` throws, or "(no error)".
std::string error_of(const std::function<void()>& body) {
    try {
        body();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

/// The message of the error a render session reports for a job.
std::string render_error(const RenderJob& job) {
    RenderSession session;
    session.set_job(job);
    session.start();
    return error_of([&] { session.wait(); });
}

/// A red ball at the origin, seen from z = 5, lit from the front, blue background.
JobBuilder red_ball_scene(int size = 16) {
    JobBuilder b(size, size);
    b.add(NodeKind::sphere, b.material({0.8, 0.1, 0.1}));
    b.light({0, 0, 10}, {1, 1, 1});
    b.camera({0, 0, 5}, {0, 0, -1}, 50);
    b.job.miss_colour = {0, 0, 1};
    b.job.options.disable_aa = true;
    return b;
}

int add_node(JobBuilder& b, NodeKind kind, int material = -1) {
    NodeDesc n;
    n.kind = kind;
    n.name = "n";
    n.name += std::to_string(b.scene->nodes.size());
    n.material = material;
    n.where = {"deep.lua", static_cast<int>(b.scene->nodes.size())};
    b.scene->nodes.push_back(n);
    return static_cast<int>(b.scene->nodes.size()) - 1;
}

int add_csg(JobBuilder& b, NodeKind kind, int left, int right) {
    const int n = add_node(b, kind);
    b.scene->nodes[n].csg_left = left;
    b.scene->nodes[n].csg_right = right;
    return n;
}

bool reddish(const glm::vec3& c) { return c.x > 0.2f && c.x > 2.0f * c.z; }
bool background(const glm::vec3& c) { return c == glm::vec3(0, 0, 1); }

}  // namespace

// ---- R3: nesting depth is not limited by the C stack ----

TEST(HardeningDepth, NodeChainOf100000FlattensOnA256KiBStack) {
    JobBuilder b = red_ball_scene();
    b.scene->nodes[0].children.clear();
    int parent = 0;
    constexpr int depth = 100'000;
    for (int i = 0; i < depth; ++i) {
        parent = b.add(NodeKind::group, -1, parent);
        b.translate(parent, {2e-5, 0, 0});  // the ball ends up at x = 2
    }
    b.add(NodeKind::sphere, 0, parent);
    FlatScene flat;
    run_with_small_stack(256 * 1024, [&] { flat = flatten_scene(*b.scene, 0, false); });
    ASSERT_EQ(flat.primitives.size(), 1u);
    EXPECT_NEAR(flat.primitives[0].object_to_world[3].x, 2.0, 1e-9);
    EXPECT_EQ(flat.primitives[0].material, 0);

    // The same job renders (render and preview share RenderSession): the ball is right of centre.
    const Image image = caustica::testing::render(b.build());
    EXPECT_TRUE(background(image.at(8, 8)));
    EXPECT_TRUE(reddish(image.at(13, 8)));
}

TEST(HardeningDepth, CycleAtTheEndOfADeepChainIsAnError) {
    JobBuilder b(8, 8);
    int parent = 0;
    for (int i = 0; i < 100'000; ++i) parent = b.add(NodeKind::group, -1, parent);
    b.scene->nodes[parent].children.push_back(0);
    b.scene->nodes[0].where = {"deep.lua", 3};
    EXPECT_EQ(error_of([&] { flatten_scene(*b.scene, 0, false); }), "deep.lua:3: node 'root' contains itself");
}

TEST(HardeningDepth, ReuseThatExpandsBeyondFiveMillionNodesIsRefused) {
    // 40 levels, each holding the next level twice: 2^40 paths to the ball.
    JobBuilder b(8, 8);
    int parent = 0;
    for (int i = 0; i < 40; ++i) {
        const int next = add_node(b, NodeKind::group);
        b.scene->nodes[parent].children = {next, next};
        parent = next;
    }
    b.scene->nodes[parent].children = {add_node(b, NodeKind::sphere, b.material({1, 1, 1}))};
    const std::string message = error_of([&] { flatten_scene(*b.scene, 0, false); });
    EXPECT_NE(message.find("expands to more than 5000000 nodes"), std::string::npos) << message;
    EXPECT_EQ(message.rfind("deep.lua:", 0), 0u) << message;
}

TEST(HardeningDepth, DifferenceChainOf100000Renders) {
    // ((ball - far_1) - far_2) ... with a box through the middle subtracted half way down: the
    // chain cannot be rebalanced, so building and tracing it must not recurse per level.
    JobBuilder b = red_ball_scene();
    b.scene->nodes[0].children.clear();
    const int red = 0;
    int solid = add_node(b, NodeKind::sphere);
    constexpr int depth = 100'000;
    for (int i = 1; i <= depth; ++i) {
        int cut;
        if (i == depth / 2) {
            cut = add_node(b, NodeKind::cube);  // a square hole along z through the ball
            b.scale(cut, {0.3, 0.3, 3});
        } else {
            cut = add_node(b, NodeKind::sphere);  // far outside the view
            b.translate(cut, {1000.0 + i, 0, 0});
        }
        solid = add_csg(b, NodeKind::csg_difference, solid, cut);
    }
    b.scene->nodes[solid].material = red;
    b.scene->nodes[0].children = {solid};
    const FlatScene flat = flatten_scene(*b.scene, 0, false);
    ASSERT_EQ(flat.csg_objects.size(), 1u);
    EXPECT_EQ(flat.csg_objects[0].leaves.size(), static_cast<std::size_t>(depth + 1));

    // Rendering runs on the session's and TBB's threads (8 and 4 MiB stacks): a recursive build
    // or evaluation needs about 100 MiB here.
    const Image image = caustica::testing::render(b.build());
    EXPECT_TRUE(background(image.at(8, 8))) << "the hole";
    EXPECT_TRUE(reddish(image.at(10, 8))) << "the ball beside the hole";
    EXPECT_TRUE(background(image.at(0, 0)));
}

// ---- R4: far cameras, lights and geometry are refused with their line, or traced safely ----

TEST(HardeningRange, FarCameraLightAndGeometryAreRefusedWithTheirLine) {
    {
        JobBuilder b = red_ball_scene();
        b.job.where = {"scene.lua", 4};
        b.camera({0, 0, 1e20}, {0, 0, -1});
        EXPECT_EQ(render_error(b.build()),
                  "scene.lua:4: gr.render: eye (0, 0, 1e+20) is beyond the renderer's range: every coordinate must "
                  "be within +-1e+18 (single-precision rays)");
    }
    {
        JobBuilder b = red_ball_scene();
        b.scene->lights[0].position = {1e308, 5, 5};
        b.scene->lights[0].where = {"scene.lua", 8};
        EXPECT_EQ(render_error(b.build()),
                  "scene.lua:8: gr.light: position (1e+308, 5, 5) is beyond the renderer's range: every coordinate "
                  "must be within +-1e+18 (single-precision rays)");
        b.scene->lights[0].position = {9e17, 0, 0};
        b.scene->lights[0].radius = 2e17;  // the sphere reaches past 1e18
        EXPECT_NE(render_error(b.build()).find("scene.lua:8: gr.light: position"), std::string::npos);
    }
    {
        JobBuilder b = red_ball_scene();
        TransformOp op;
        op.amount = {0, 2e18, 0};
        op.where = {"scene.lua", 6};
        b.scene->nodes[1].transforms.push_back(op);
        EXPECT_EQ(render_error(b.build()),
                  "scene.lua:6: node:translate: translation (0, 2e+18, 0) is beyond the renderer's range: every "
                  "coordinate must be within +-1e+18 (single-precision rays)");
        b.scene->nodes[1].transforms[0].kind = TransformOp::Kind::scale;
        b.scene->nodes[1].transforms[0].amount = {1, 1e-30, 1};
        EXPECT_NE(render_error(b.build()).find("scene.lua:6: node:scale: scale factor 1e-30"), std::string::npos);
    }
    {
        // Each call is within range; together they move the ball to 1.5e18.
        JobBuilder b = red_ball_scene();
        b.scene->nodes[1].where = {"scene.lua", 2};
        const int group = b.add(NodeKind::group, -1);
        b.translate(group, {0, 0, 9e17});
        b.scene->nodes[group].children = {1};
        b.scene->nodes[0].children = {group};
        b.translate(1, {0, 0, 6e17});
        EXPECT_EQ(render_error(b.build()),
                  "scene.lua:2: gr.sphere: node 'node1' is scaled or moved beyond the renderer's range by its "
                  "transforms (every matrix entry, and its inverse's, within +-1e+18)");
        // A transform within range that makes the ball reach past 1e18.
        b.scene->nodes[group].transforms.clear();
        b.scene->nodes[1].transforms.clear();
        b.translate(1, {0, 0, 6e17});
        b.scale(1, {6e17, 6e17, 6e17});
        EXPECT_EQ(render_error(b.build()),
                  "scene.lua:2: gr.sphere: node 'node1' reaches (-6e+17, -6e+17, 1.2e+18) in world space, beyond "
                  "the renderer's range: every coordinate must be within +-1e+18 (single-precision rays)");
    }
}

TEST(HardeningRange, SceneAtTheCoordinateLimitRendersFinite) {
    // The eye, a spherical light and geometry just inside +-1e18, with caustics: no Embree abort,
    // no NaN.
    JobBuilder b(24, 24);
    MaterialDesc glass;
    glass.ks = {0.9, 0.9, 0.9};
    glass.refractive_index = 1.5;
    b.scene->materials.push_back(glass);
    const int g = static_cast<int>(b.scene->materials.size()) - 1;
    const int red = b.material({0.8, 0.2, 0.2}, {0.5, 0.5, 0.5}, 20);
    const int far = b.add(NodeKind::sphere, red);
    b.translate(far, {0, 0, -9e17});
    b.scale(far, {5e16, 5e16, 5e16});
    const int ball = b.add(NodeKind::sphere, g);
    b.translate(ball, {0, 0, 9.9e17});
    const int floor = b.add(NodeKind::cube, red);
    b.translate(floor, {0, -2, 9.9e17});
    b.scale(floor, {5, 0.1, 5});
    b.light({9.9e17, 9.9e17, -9.9e17}, {1, 1, 1}, {1, 0, 1e-30});
    b.scene->lights[0].radius = 1e15;
    b.light({0, 5, 9.9e17}, {1, 1, 1}, {0, 0, 1});
    b.camera({0, 0, 1e18}, {0, 0, -1}, 40);
    b.job.options.caustic_num_photons = 20'000;
    b.job.options.disable_aa = true;
    const Image image = caustica::testing::render(b.build());
    EXPECT_EQ(non_finite_pixels(image), 0u);
}

TEST(HardeningRange, UntraceableRaysAreAMissNotAnEmbreeAbort) {
    JobBuilder b = red_ball_scene();
    const RenderScene scene(*b.scene, flatten_scene(*b.scene, 0, false));
    SurfaceHit hit;
    EXPECT_TRUE(scene.intersect(Ray{{0, 0, 5}, {0, 0, -1}, 0.0f, ray_infinity}, hit));
    EXPECT_FALSE(scene.intersect(Ray{{0, 0, 1e30f}, {0, 0, -1}, 0.0f, ray_infinity}, hit));
    const float nan = std::nanf("");
    EXPECT_FALSE(scene.intersect(Ray{{0, 0, 5}, {nan, 0, -1}, 0.0f, ray_infinity}, hit));
    EXPECT_TRUE(scene.occluded(Ray{{0, 0, 1e30f}, {0, 0, -1}, 0.0f, ray_infinity}));
    Ray rays[8];
    int valid[8];
    bool found[8], blocked[8];
    SurfaceHit hits[8];
    for (int i = 0; i < 8; ++i) {
        rays[i] = Ray{{0, 0, i == 3 ? 1e30f : 5.0f}, {0, 0, -1}, 0.0f, ray_infinity};
        valid[i] = 1;
    }
    scene.intersect8(rays, valid, hits, found);
    scene.occluded8(rays, valid, blocked);
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(found[i], i != 3) << i;
        EXPECT_TRUE(blocked[i]) << i;
    }
}

// ---- N1: no NaN or infinity reaches the image from finite input ----

TEST(HardeningNumbers, AbsurdColoursAndFalloffsAreRefusedWithTheirLine) {
    JobBuilder b = red_ball_scene();
    b.scene->materials[0].ks = {1e308, 0.5, 0.5};
    b.scene->materials[0].where = {"scene.lua", 1};
    EXPECT_EQ(render_error(b.build()),
              "scene.lua:1: gr.material: ks[1] = 1e+308 is outside the renderer's range [0, 1e+06] for colours");
    b.scene->materials[0].ks = {0, 0, 0};
    b.scene->lights[0].falloff = {1e-308, 0, 0};
    b.scene->lights[0].where = {"scene.lua", 2};
    EXPECT_EQ(render_error(b.build()),
              "scene.lua:2: gr.light: falloff c0 = 1e-308 is outside the renderer's range: each coefficient must be "
              "0 or between 1e-30 and 1e+30");
    b.scene->lights[0].falloff = {1, 0, 0};
    b.job.ambient = {0, 1e308, 0};
    b.job.where = {"scene.lua", 3};
    EXPECT_EQ(render_error(b.build()),
              "scene.lua:3: gr.render: ambient[2] = 1e+308 is outside the renderer's range [0, 1e+06] for colours");
    b.job.ambient = {0, 0, 0};
    b.scene->materials[0].refractive_index = 1e300;
    EXPECT_EQ(render_error(b.build()).rfind("scene.lua:1: material:set_ri: refractive index 1e+300", 0), 0u);
}

namespace {

/// Colours at 1e6 everywhere (kd, ks, lights, ambient, miss colour, a medium colour), a light
/// with c0 = 1e-30 (attenuation 1e30 before the cap), glass of index 1e6, 1e-6 and 1.5, shininess
/// 1e6, and per case: photons of power up to 2.5e29 gathered over a tiny disc, a unit distance below
/// float (the medium's transmittance 1e6^inf), a large one, and mirrors of ks = 1e6 facing each
/// other 64 bounces deep (caustics refuse such mirrors: kd + ks > 1). Renders each case with
/// `kind` and checks that every pixel is finite and that the caustic stage ran.
void expect_extremes_give_finite_pixels(IntegratorKind kind) {
    struct Case {
        double unit_distance;
        bool caustics;
    };
    for (const Case c : {Case{1e-2, true}, Case{1e-300, true}, Case{1e12, true}, Case{1.0, false}}) {
        JobBuilder b(16, 16);
        b.job.options.integrator = kind;
        const double mirror_ks = c.caustics ? 1.0 : 1e6;
        const int mirror = b.material({0, 0, 0}, glm::dvec3(mirror_ks), 1e6, true);
        const int diffuse = b.material({1e6, 0, 1e6}, {1e6, 0, 0}, 1e6);
        for (const double index : {1e6, 1e-6, 1.5}) {
            MaterialDesc glass;
            glass.kd = {1e6, 0.5, 0};  // the surface's diffuse colour
            glass.ks = {1e6, 1e6, 0};  // the medium's colour, transmittance 1e6^(d / unit distance)
            glass.refractive_index = index;
            b.scene->materials.push_back(glass);
        }
        const int glass = static_cast<int>(b.scene->materials.size()) - 3;
        for (const double x : {-2.0, 2.0}) {
            const int wall = b.add(NodeKind::cube, mirror);
            b.translate(wall, {x, 0, 0});
            b.scale(wall, {0.1, 3, 3});
        }
        const int floor = b.add(NodeKind::cube, diffuse);
        b.translate(floor, {0, -1.5, 0});
        b.scale(floor, {3, 0.1, 3});
        const int ball = b.add(NodeKind::sphere, glass);
        b.translate(ball, {-0.5, -0.8, 1});
        b.scale(ball, {0.5, 0.5, 0.5});
        const int ball2 = b.add(NodeKind::sphere, glass + 1);
        b.translate(ball2, {1, -0.8, 1});
        b.scale(ball2, {0.4, 0.4, 0.4});
        const int ball3 = b.add(NodeKind::sphere, glass + 2);
        b.translate(ball3, {0.25, -0.5, 2});
        b.scale(ball3, {0.3, 0.3, 0.3});
        b.light({0, 1, 0}, {1e6, 1e6, 1e6}, {1e-30, 0, 0});
        // c2 as small as the photon power allows: 1e6 x 4 pi u^2 / (c2 x 5000) <= 1e30.
        b.light({0.5, 0.5, 1.5}, {1e6, 1e6, 1e6}, {0, 0, c.unit_distance > 1.0 ? 1.0 : 1e-30});
        b.scene->lights[1].radius = 0.01;
        b.camera({0, 0, 4}, {0, -0.2, -1}, 60);
        b.job.ambient = {1e6, 1e6, 1e6};
        b.job.miss_colour = {1e6, 1e6, 1e6};
        b.job.options.max_depth = c.caustics ? 24 : 64;
        b.job.options.shadow_grid = 2;
        b.job.options.unit_distance = c.unit_distance;
        b.job.options.caustic_num_photons = c.caustics ? 5'000 : 0;
        b.job.options.caustic_num_neighbours = 1;
        b.job.options.aa_grid = 2;
        RenderSession session;
        session.set_job(b.build());
        session.start();
        ASSERT_TRUE(session.wait()) << c.unit_distance;
        EXPECT_EQ(non_finite_pixels(session.image()), 0u) << "unit distance " << c.unit_distance;
        EXPECT_GT(session.stats().rays.refracted, 0u);  // the medium was crossed
        if (c.caustics) {
            // At d_u = 1e-300 the photon energy 4 pi d_u^2 C / (c2 N) underflows to exactly 0 in
            // double. The progressive map stores such photons; the classic map stores a photon only
            // if its luma is > 0, so the classic map stays empty there (the rule, not a failure).
            if (kind == IntegratorKind::classic && c.unit_distance < 1e-150)
                EXPECT_EQ(session.stats().caustic_photons, 0u) << c.unit_distance;
            else
                EXPECT_GT(session.stats().caustic_photons, 0u) << c.unit_distance;
        }
    }
}

}  // namespace

TEST(HardeningNumbers, ExtremesWithinTheLimitsGiveFinitePixels) {
    expect_extremes_give_finite_pixels(IntegratorKind::progressive);
}

TEST(HardeningNumbers, ExtremesWithinTheLimitsGiveFinitePixelsWithTheClassicIntegrator) {
    // docs/RELIABILITY.md "No NaN or infinity from finite input" holds for every integrator.
    expect_extremes_give_finite_pixels(IntegratorKind::classic);
}

TEST(HardeningNumbers, PhotonPowerBeyondFloatIsRefusedAtTheLight) {
    // --unit-distance 1e30 (its maximum) with an ordinary light: each photon would carry ~1e56.
    JobBuilder b = caustica::testing::virtual_light_scene(false);
    b.scene->lights[0].where = {"scene.lua", 9};
    b.job.options.caustic_num_photons = 10'000;
    b.job.options.unit_distance = 1e30;
    const std::string message = render_error(b.build());
    EXPECT_EQ(message.rfind("scene.lua:9: gr.light: each caustic photon would carry a power of 1.2", 0), 0u) << message;
    EXPECT_NE(message.find("lower --unit-distance"), std::string::npos);
    // Without caustics the same unit distance renders.
    b.job.options.caustic_num_photons = 0;
    EXPECT_EQ(non_finite_pixels(caustica::testing::render(b.build())), 0u);
}

// ---- R5: options that size per-thread scratch are bounded, with the reason ----

TEST(HardeningOptions, NeighboursAndProjectionMapSizeAreBounded) {
    Options o;
    EXPECT_EQ(error_of([&] { apply_option_tokens(o, {"--caustic-num-neighbours", "2147483647"}); }),
              "--caustic-num-neighbours: 2147483647 is out of range [1, 1000000]: every render thread keeps a search "
              "buffer of N photons (8 bytes each), and an estimate over more than a million photons is a blur");
    apply_option_tokens(o, {"--caustic-num-neighbours", "1000000"});
    EXPECT_EQ(o.caustic_num_neighbours, 1'000'000);
    EXPECT_NE(error_of([&] { apply_option_tokens(o, {"--caustic-pm-gran", "8192"}); }).find("[2, 4096]: each light's map"),
              std::string::npos);
    apply_option_tokens(o, {"--caustic-pm-gran", "4096"});
    EXPECT_EQ(o.caustic_pm_gran, 4096);
}

// ---- B1: OBJ polygons of any size, indices checked with their line ----

TEST(HardeningObj, PolygonOf300CornersIsFannedWhole) {
    std::string text;
    for (int i = 0; i < 300; ++i) {
        const double a = 2.0 * 3.14159265358979 * i / 300.0;
        text += "v ";
        text += std::to_string(std::cos(a));
        text += ' ';
        text += std::to_string(std::sin(a));
        text += " 0\n";
    }
    text += "f";
    for (int i = 1; i <= 300; ++i) {
        text += ' ';
        text += std::to_string(i);
    }
    text += "\n";
    const auto mesh = parse_obj_mesh(text, "polygon300.obj");
    ASSERT_EQ(mesh->triangles.size(), 298u);
    for (std::size_t k = 0; k < 298; ++k)
        EXPECT_EQ(mesh->triangles[k], glm::uvec3(0, k + 1, k + 2)) << k;
    EXPECT_EQ(mesh->path, "polygon300.obj");
}

TEST(HardeningObj, BadIndicesAndNumbersNameTheFileAndLine) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const auto error = [](const std::string& text) { return error_of([&] { parse_obj_mesh(text, "mesh.obj"); }); };
    EXPECT_EQ(error(tri + "f 1 2 99999999999999999999\n"), "mesh.obj:4: face index 99999999999999999999 is out of range (1..3)");
    EXPECT_EQ(error(tri + "f 1 2 -99999999999999999999\n"),
              "mesh.obj:4: face index -99999999999999999999 is out of range (-1..-3)");
    EXPECT_EQ(error(tri + "# comment\nf 1 2 9\n"), "mesh.obj:5: face index 9 is out of range (1..3)");
    EXPECT_EQ(error(tri + "f -1 -2 -4\n"), "mesh.obj:4: face index -4 is out of range (-1..-3)");
    EXPECT_EQ(error(tri + "f 0 1 2\n"), "mesh.obj:4: face index 0 is out of range (1..3)");
    EXPECT_EQ(error(tri + "f 1 2 x\n"), "mesh.obj:4: face index 'x' is not a whole number");
    EXPECT_EQ(error(tri + "vt 0 0\nf 1/1 2/2 3/1\n"), "mesh.obj:5: texture coordinate index 2 is out of range (1..1)");
    EXPECT_EQ(error("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "mesh.obj:2: coordinate 'nan' is not a finite number");
    EXPECT_EQ(error("v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "mesh.obj:1: coordinate '1e39' is out of range");
    EXPECT_EQ(error("v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "mesh.obj:1: coordinate '1e999' is out of range");
    EXPECT_EQ(error("v 0 0\n"), "mesh.obj:1: a vertex needs x, y and z");
    EXPECT_EQ(error(tri), "mesh.obj: no triangles (the file has no faces with 3 or more vertices)");
}

TEST(HardeningObj, RelativeIndicesForwardIndicesAndCornerForms) {
    const auto mesh = parse_obj_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nvn 0 0 1\n"
                                     "f -3 -2 -1\n"
                                     "f 1/1 2//1 3/-1/1 4\n"
                                     "v +1 1 0\n",
                                     "forms.obj");
    ASSERT_EQ(mesh->positions.size(), 4u);
    EXPECT_EQ(mesh->positions[3], glm::vec3(1, 1, 0));
    ASSERT_EQ(mesh->triangles.size(), 3u);
    EXPECT_EQ(mesh->triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh->triangles[1], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh->triangles[2], glm::uvec3(0, 2, 3));
    ASSERT_EQ(mesh->texcoords.size(), 9u);
    EXPECT_EQ(mesh->texcoords[0], glm::vec2(0.0f));       // the first face had none
    EXPECT_EQ(mesh->texcoords[3], glm::vec2(0.5f, 0.25f));
    EXPECT_EQ(mesh->texcoords[4], glm::vec2(0.0f));       // 2//1: a normal, no texture coordinate
    EXPECT_EQ(mesh->texcoords[5], glm::vec2(0.5f, 0.25f));
}

// ---- U1: fingerprints hash indices in unsigned arithmetic, without collisions ----

TEST(HardeningHash, LargeOperandAndTextureIndicesGiveDistinctFingerprints) {
    // (left + 1) * 65536 + right + 1 overflowed int at 32768 and made (0, 65536) equal (1, 0).
    JobBuilder b(8, 8);
    for (int i = 0; i < 65'537; ++i) add_node(b, NodeKind::sphere);
    const int c = add_csg(b, NodeKind::csg_union, 0, 65'536);
    RenderJob first = b.build();
    b.scene = std::make_shared<SceneDesc>(*b.scene);
    b.scene->nodes[c].csg_left = 1;
    b.scene->nodes[c].csg_right = 0;
    EXPECT_NE(geometry_fingerprint(first), geometry_fingerprint(b.build()));

    JobBuilder t(8, 8);
    t.scene->textures.resize(65'537);
    const int m = t.material({1, 1, 1});
    t.scene->materials[m].texture = 0;
    t.scene->materials[m].bumpmap = 65'536;
    const RenderJob textured = t.build();
    t.scene = std::make_shared<SceneDesc>(*t.scene);
    t.scene->materials[m].texture = 1;
    t.scene->materials[m].bumpmap = 0;
    EXPECT_NE(geometry_fingerprint(textured), geometry_fingerprint(t.build()));
}

// ---- L1: the denormal mode is set per task, with nothing left allocated ----

TEST(HardeningDenormals, ScopedFlushSetsAndRestoresTheMode) {
    const unsigned before = _mm_getcsr();
    _mm_setcsr(before & ~(_MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON));
    {
        const ScopedFlushDenormals flush;
        EXPECT_EQ(_MM_GET_FLUSH_ZERO_MODE(), static_cast<unsigned>(_MM_FLUSH_ZERO_ON));
        EXPECT_EQ(_MM_GET_DENORMALS_ZERO_MODE(), static_cast<unsigned>(_MM_DENORMALS_ZERO_ON));
        volatile float tiny = 1e-39f;  // a denormal: read as zero
        EXPECT_EQ(tiny * 1.0f, 0.0f);
    }
    EXPECT_EQ(_MM_GET_FLUSH_ZERO_MODE(), 0u);
    EXPECT_EQ(_MM_GET_DENORMALS_ZERO_MODE(), 0u);
    _mm_setcsr(before);
}
