// The classic integrator against docs/CAUSTICS.md, "The two integrators, rule by rule" (and the
// rules of docs/SCENE_LANGUAGE.md that both integrators share), rule by rule: each test's expected
// value is the closed form of its rule, and each would fail without that rule.
#include "core/geometry/render_scene.h"
#include "core/integrators/classic.h"
#include "core/integrators/progressive.h"
#include "core/integrators/shading_common.h"
#include "core/render/tile_renderer.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

constexpr float pi = 3.14159265358979f;

/// A large diffuse floor whose top face is the plane y = 0.
int add_floor(JobBuilder& b, int material) {
    const int floor = b.add(NodeKind::cube, material);
    b.translate(floor, {0, -1, 0});
    b.scale(floor, {100, 1, 100});
    return floor;
}

glm::vec3 render_one_pixel(JobBuilder& b, IntegratorKind kind) {
    b.job.width = b.job.height = 1;
    b.job.options.disable_aa = true;
    b.job.options.integrator = kind;
    return caustica::testing::render(b.build()).at(0, 0);
}

void expect_colour(const glm::vec3& got, const glm::vec3& want, float tolerance, const char* what) {
    EXPECT_NEAR(got.x, want.x, tolerance) << what;
    EXPECT_NEAR(got.y, want.y, tolerance) << what;
    EXPECT_NEAR(got.z, want.z, tolerance) << what;
}

}  // namespace

// "Phong": colour = A kd + C [kd + ks max(r.v,0)^p (n.l)] (n.l) / (c0 + c1 d + c2 d^2),
// d = |L - P| / d_u.
TEST(SceneLanguagePhong, SpecularCarriesNdotLSquaredAndFalloffIsInUnitDistances) {
    for (IntegratorKind kind : {IntegratorKind::classic, IntegratorKind::progressive}) {
        JobBuilder b(1, 1);
        add_floor(b, b.material({0.5, 0.5, 0.5}, {0.3, 0.3, 0.3}, 1.0));
        b.light({1, 1, 0}, {1, 1, 1}, {0.5, 1.0, 2.0});
        b.camera({0, 2, 0}, {0, -1, 0}, 30, {0, 0, -1});
        b.job.ambient = {0.1, 0.1, 0.1};
        b.job.options.unit_distance = 2.0;
        const float n_dot_l = std::sqrt(0.5f), r_dot_v = std::sqrt(0.5f);
        const float d = std::sqrt(2.0f) / 2.0f;
        const float expected = 0.1f * 0.5f + (0.5f + 0.3f * r_dot_v * n_dot_l) * n_dot_l / (0.5f + d + 2.0f * d * d);
        expect_colour(render_one_pixel(b, kind), glm::vec3(expected), 2e-5f,
                      kind == IntegratorKind::classic ? "classic" : "progressive");
    }
}

// "background": the default miss colour is white; --rays shows the orange sunburst.
TEST(SceneLanguageBackground, MissIsWhiteByDefaultAndRaysShowsTheSunburst) {
    for (IntegratorKind kind : {IntegratorKind::classic, IntegratorKind::progressive}) {
        JobBuilder b(1, 1);
        b.camera({0, 0, 0}, {0, 0, -1}, 30);
        expect_colour(render_one_pixel(b, kind), glm::vec3(1.0f), 0.0f, "default miss colour");
    }
    // k = floor(theta 28 / 2 pi - 1/2): theta = 0 gives k = -1 (odd), theta = 2 pi / 28 gives k = 0.
    const glm::vec3 right(1, 0, 0), up(0, 1, 0);
    const auto at = [&](float theta) { return sunburst(glm::vec3(std::cos(theta), std::sin(theta), -5.0f), right, up); };
    expect_colour(at(0.0f), {1.0f, 0.56f, 0.0f}, 0.0f, "theta 0");
    expect_colour(at(2.0f * pi / 28.0f), {1.0f, 0.29f, 0.0f}, 0.0f, "theta 2 pi / 28");
    expect_colour(at(2.0f * pi / 28.0f * 1.49f), {1.0f, 0.29f, 0.0f}, 0.0f, "inside sector 0");
    expect_colour(at(2.0f * pi / 28.0f * 1.51f), {1.0f, 0.56f, 0.0f}, 0.0f, "sector 1");
    expect_colour(at(-2.0f * pi / 28.0f), {1.0f, 0.29f, 0.0f}, 0.0f, "sector -2");
    JobBuilder b(1, 1);
    b.camera({0, 0, 0}, {0, 0, -1}, 30);
    b.job.options.rays = true;
    // The centre ray looks along the view axis: x = y = 0, theta = atan2(0, 0) = 0, sector -1.
    expect_colour(render_one_pixel(b, IntegratorKind::classic), {1.0f, 0.56f, 0.0f}, 0.0f, "--rays");
}

namespace {

/// Two parallel mirrors facing each other (z = -1 and z = +1), the camera between them looking
/// along -z: the centre ray bounces between them forever.
JobBuilder mirror_corridor(double ks, double kd, double ambient) {
    JobBuilder b(1, 1);
    const int m = b.material(glm::dvec3(kd), glm::dvec3(ks), 10, true);
    const int front = b.add(NodeKind::cube, m);
    b.translate(front, {0, 0, -2});
    b.scale(front, {50, 50, 1});
    const int back = b.add(NodeKind::cube, m);
    b.translate(back, {0, 0, 2});
    b.scale(back, {50, 50, 1});
    b.camera({0, 0, 0}, {0, 0, -1}, 10);
    b.job.ambient = glm::dvec3(ambient);
    return b;
}

}  // namespace

// "deep rays": a ray deeper than 15 that hits something returns white: 16 mirror reflections of
// ks = 0.9.
TEST(ClassicViewRays, DepthAboveFifteenReturnsWhite) {
    JobBuilder b = mirror_corridor(0.9, 0.0, 0.0);
    const float expected = std::pow(0.9f, 16.0f);
    expect_colour(render_one_pixel(b, IntegratorKind::classic), glm::vec3(expected), 1e-5f, "0.9^16 x white");
}

// "view-ray cut": a reflection is traced only while weight Y(ks) > 0.02: with ks = 0.7 the ray at
// depth 10 is the last, and each hit adds its ambient kd A weighted by 0.7^depth.
TEST(ClassicViewRays, LumaWeightCutsReflectionsBelowTwoPercent) {
    JobBuilder b = mirror_corridor(0.7, 0.1, 1.0);
    float expected = 0.0f;
    for (int depth = 0; depth <= 10; ++depth) expected += 0.1f * std::pow(0.7f, static_cast<float>(depth));
    expect_colour(render_one_pixel(b, IntegratorKind::classic), glm::vec3(expected), 1e-5f, "sum to depth 10");
}

namespace {

/// A slab of index 1 (no reflection, no bending) and ks `tint`, 0.5 thick (z in [-0.25, 0.25]),
/// before a white wall whose front is at z = -0.25 - gap; the wall shows exactly 1 (ambient 1,
/// kd 1). With `csg`, the slab is the union of two halves.
JobBuilder tinted_slab(glm::dvec3 tint, double gap, bool csg, double scale = 1.0) {
    JobBuilder b(1, 1);
    MaterialDesc glass;
    glass.ks = tint;
    glass.refractive_index = 1.0;
    b.scene->materials.push_back(glass);
    const int glass_material = static_cast<int>(b.scene->materials.size()) - 1;
    const int root = b.add(NodeKind::group, -1);
    b.scale(root, glm::dvec3(scale));
    if (!csg) {
        const int slab = b.add(NodeKind::cube, glass_material, root);
        b.scale(slab, {3, 3, 0.25});
    } else {
        NodeDesc u;
        u.kind = NodeKind::csg_union;
        u.name = "slab";
        u.material = glass_material;
        b.scene->nodes.push_back(u);
        const int union_node = static_cast<int>(b.scene->nodes.size()) - 1;
        b.scene->nodes[root].children.push_back(union_node);
        const int left = b.add(NodeKind::cube, glass_material, root);
        const int right = b.add(NodeKind::cube, glass_material, root);
        b.scene->nodes[root].children.resize(b.scene->nodes[root].children.size() - 2);  // operands only
        b.translate(left, {-1.5, 0, 0});
        b.scale(left, {1.5, 3, 0.25});
        b.translate(right, {1.5, 0, 0});
        b.scale(right, {1.5, 3, 0.25});
        b.scene->nodes[union_node].csg_left = left;
        b.scene->nodes[union_node].csg_right = right;
    }
    const int wall = b.add(NodeKind::cube, b.material({1, 1, 1}), root);
    b.translate(wall, {0, 0, -1.25 - gap});
    b.scale(wall, {5, 5, 1});
    b.camera(glm::dvec3(0.2, 0, 5) * scale, {0, 0, -1}, 10);
    b.job.ambient = {1, 1, 1};
    b.job.options.unit_distance = scale;
    return b;
}

}  // namespace

// "medium colour" and "media": a transmitted view ray carries (1 - R) ks^(d/d_u); for a plain
// (non-CSG) object the segment after leaving it is still coloured by its own ks, up to the next
// surface.
TEST(ClassicMedia, PlainObjectColoursTheSegmentsOnBothSides) {
    const glm::dvec3 tint(0.5, 0.8, 1.0);
    JobBuilder b = tinted_slab(tint, 1.0, false);
    const float inside = 0.5f, after = 1.0f;  // slab thickness, then the gap to the wall
    const glm::vec3 expected(std::pow(0.5f, inside + after), std::pow(0.8f, inside + after), 1.0f);
    expect_colour(render_one_pixel(b, IntegratorKind::classic), expected, 1e-4f, "ks^(0.5 + 1)");
}

// "CSG media": inside a CSG the far side's material colours the segment: air after leaving.
TEST(ClassicMedia, CsgInterfaceColoursOnlyTheInside) {
    JobBuilder b = tinted_slab({0.5, 0.8, 1.0}, 1.0, true);
    const glm::vec3 expected(std::pow(0.5f, 0.5f), std::pow(0.8f, 0.5f), 1.0f);
    expect_colour(render_one_pixel(b, IntegratorKind::classic), expected, 1e-4f, "ks^0.5, then air");
}

// Scale invariance: scaling the scene and the unit distance together changes nothing.
TEST(ClassicMedia, ScaleInvarianceWithTheUnitDistanceInBothIntegrators) {
    for (IntegratorKind kind : {IntegratorKind::classic, IntegratorKind::progressive}) {
        JobBuilder small = tinted_slab({0.5, 0.8, 1.0}, 1.0, false, 1.0);
        JobBuilder large = tinted_slab({0.5, 0.8, 1.0}, 1.0, false, 7.0);
        const glm::vec3 a = render_one_pixel(small, kind), c = render_one_pixel(large, kind);
        expect_colour(c, a, 1e-4f, kind == IntegratorKind::classic ? "classic" : "progressive");
        EXPECT_LT(a.x, 0.99f);  // the medium did something
    }
}

// "soft shadows": a regular N x N grid of directions over the square of half-width sin(theta) (no
// jitter, no disc): with the blocker's edge between the first and second columns, exactly 1/4 is
// hidden.
TEST(ClassicShadows, RegularGridOverTheSquareWithoutJitter) {
    JobBuilder b(8, 8);
    const int slab = b.add(NodeKind::cube, b.material({0, 0, 0}));
    b.translate(slab, {-50.25, 5, 0});  // covers x < -0.25 at height 5
    b.scale(slab, {50, 0.01, 50});
    const RenderJob job = b.build();
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
    ShadingSetup setup;
    setup.scene = &scene;
    setup.shadow_grid = 4;
    const ClassicIntegrator integrator(setup);
    Light light;
    light.position = {0, 10, 0};
    light.radius = 1.0f;  // sin(theta) = 0.1: columns at x = 10 * 0.1 * {-0.75, -0.25, 0.25, 0.75} / 2 at y = 5
    RayCounters counters;
    EXPECT_FLOAT_EQ(integrator.light_visibility(light, {0, 0, 0}, counters), 0.75f);
    EXPECT_EQ(counters.shadow, 16u);
    // The same point, twice: no randomness.
    EXPECT_FLOAT_EQ(integrator.light_visibility(light, {0, 0, 0}, counters), 0.75f);
    setup.shadow_grid = 1;  // grid <= 1: one ray to the centre, which passes
    EXPECT_FLOAT_EQ(ClassicIntegrator(setup).light_visibility(light, {0, 0, 0}, counters), 1.0f);
    setup.shadow_grid = 4;
    setup.soft_shadows = false;
    EXPECT_FLOAT_EQ(ClassicIntegrator(setup).light_visibility(light, {0, 0, 0}, counters), 1.0f);
}

namespace {

/// A 1 x 1 image with a white stripe (ambient 1, kd 1) on black covering exactly the sample
/// column `column` of a 3 x 3 grid at ((i + 1/2) / 3, ...).
JobBuilder stripe(int column) {
    JobBuilder b(1, 1);
    b.camera({0, 0, 0}, {0, 0, -1}, 10);
    b.job.miss_colour = {0, 0, 0};
    b.job.ambient = {1, 1, 1};
    const Camera camera(b.job.camera, 1, 1);
    const auto x_at = [&](float px) {
        const Ray r = camera.generate(px, 0.5f);
        return r.origin.x + r.direction.x * (10.0f - r.origin.z) / -r.direction.z;  // at z = -10 (front face)
    };
    const float lo = x_at((static_cast<float>(column) + 0.1f) / 3.0f), hi = x_at((static_cast<float>(column) + 0.9f) / 3.0f);
    const int s = b.add(NodeKind::cube, b.material({1, 1, 1}));
    b.translate(s, {0.5 * (lo + hi), 0, -11});
    b.scale(s, {0.5 * (hi - lo), 10, 1});
    b.job.options.aa_grid = 3;
    b.job.options.aa_threshold = 0.5;
    return b;
}

glm::vec3 render_aa(JobBuilder& b) {
    b.job.options.integrator = IntegratorKind::classic;
    return caustica::testing::render(b.build()).at(0, 0);
}

}  // namespace

// "anti-aliasing": above g = 2 the four corners decide; equal corners leave the pixel at their mean
// even if the middle samples differ.
TEST(ClassicAntialiasing, FourEqualCornersAreThePixel) {
    JobBuilder b = stripe(1);  // only the middle column is white
    expect_colour(render_aa(b), glm::vec3(0.0f), 0.0f, "corners all black");
}

// "anti-aliasing": differing corners (delta = 4 pairs x 3 = 12 > 0.5) trace the rest and average
// all g^2.
TEST(ClassicAntialiasing, DifferingCornersAverageTheWholeRegularGrid) {
    JobBuilder b = stripe(0);  // the left column is white: 3 of 9 samples
    expect_colour(render_aa(b), glm::vec3(1.0f / 3.0f), 1e-6f, "3 of 9");
    JobBuilder red = stripe(0);
    red.job.options.draw_aa = true;
    expect_colour(render_aa(red), glm::vec3(1, 0, 0), 0.0f, "--draw-aa");
    JobBuilder high = stripe(0);
    high.job.options.aa_threshold = 12.5;  // delta = 12 is not above it: the four corners' mean
    expect_colour(render_aa(high), glm::vec3(0.5f), 1e-6f, "2 of 4 corners");
}

// "anti-aliasing": g <= 2 is the mean of all g^2 regular samples.
TEST(ClassicAntialiasing, SmallGridsAverageEverySample) {
    glm::vec3 corners[4] = {{1, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    EXPECT_FLOAT_EQ(corner_difference(corners), 3.0f);  // three pairs differ by 1 in red
    JobBuilder b = stripe(0);
    b.job.options.aa_grid = 2;  // samples at 1/4 and 3/4: the stripe over [0.03, 0.3] holds the left ones
    expect_colour(render_aa(b), glm::vec3(0.5f), 1e-6f, "2 of 4");
}

// "media" leaves open what colours a transmitted segment that hits nothing: we attenuate nothing
// there (an infinite ks^d would turn everything seen through a tinted plain object black).
TEST(ClassicMedia, ASegmentLeavingTheSceneIsNotAttenuated) {
    JobBuilder b = tinted_slab({0.5, 0.8, 1.0}, 1.0, false);
    // tinted_slab's nodes: 0 the root, 1 its scaled group, 2 the slab, 3 the wall (last child of 1).
    ASSERT_EQ(b.scene->nodes[1].children.back(), 3);
    b.scene->nodes[1].children.pop_back();  // no wall behind the slab
    b.job.ambient = {0, 0, 0};
    const glm::vec3 expected(std::pow(0.5f, 0.5f), std::pow(0.8f, 0.5f), 1.0f);  // inside only, then the white miss
    expect_colour(render_one_pixel(b, IntegratorKind::classic), expected, 1e-4f, "ks^0.5 x white");
}

// "option defaults": --shadow-grid also turns soft shadows on.
TEST(ClassicShadows, ShadowGridTurnsSoftShadowsOn) {
    Options o;
    apply_option_tokens(o, {"--no-soft-shadows", "--shadow-grid", "4"});
    EXPECT_FALSE(o.no_soft_shadows);
    EXPECT_EQ(o.shadow_grid, 4);
    apply_option_tokens(o, {"--no-soft-shadows"});
    EXPECT_TRUE(o.no_soft_shadows);  // a later --no-soft-shadows wins
}
