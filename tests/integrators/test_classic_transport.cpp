// The classic integrator's photon terms (docs/CAUSTICS.md, "photon emission" to "debug views")
// end to end: the caustic of a known scene against the closed form the rules give, the gates of
// the estimate, the GI term and the GI map of a closed room, each debug view on photons placed by
// hand, and switching integrator in a session.
#include "core/geometry/render_scene.h"
#include "core/integrators/classic.h"
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/classic_photons.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "tests/scene_test_helpers.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

constexpr float pi = 3.14159265358979f;

/// A floor (top face y = 0) of diffuse colour kd, seen from (0, 1, 1) at 45 degrees: the centre
/// ray hits the origin with n.v = cos 45.
struct FloorView {
    JobBuilder builder{1, 1};
    std::unique_ptr<RenderScene> scene;
    ShadingSetup setup;
    ClassicParams params;  // N 5, pruned at 0.15: the defaults
    const Ray ray{glm::vec3(0, 1, 1), glm::normalize(glm::vec3(0, -1, -1)), 0.0f, ray_infinity};

    explicit FloorView(double kd) {
        const int floor = builder.add(NodeKind::cube, builder.material(glm::dvec3(kd)));
        builder.translate(floor, {0, -1, 0});
        builder.scale(floor, {100, 1, 100});
        const RenderJob job = builder.build();
        scene = std::make_unique<RenderScene>(*job.scene, flatten_scene(*job.scene, job.root, false));
        setup.scene = scene.get();
    }

    glm::vec3 colour() const {
        const ClassicIntegrator integrator(setup, params);
        RandomStream random(1, 1);
        RayCounters counters;
        return integrator.trace_camera_ray(ray, random, counters);
    }
};

/// `count` photons of power `power` on the floor around the origin: the five nearest at 0.01 ..
/// 0.05 (or `nearest` for the first), the others from 0.5 outwards.
PhotonMap photons_around_origin(int count, glm::vec3 power, float nearest = 0.01f) {
    std::vector<Photon> photons;
    for (int i = 0; i < count; ++i) {
        const float r = i == 0 ? nearest : i < 5 ? 0.01f * static_cast<float>(i + 1) : 0.5f + 0.01f * static_cast<float>(i);
        const float angle = 2.4f * static_cast<float>(i);
        photons.push_back({glm::vec3(r * std::cos(angle), 0.0f, r * std::sin(angle)), power, glm::vec3(0, -1, 0)});
    }
    return PhotonMap(std::move(photons));
}

const float n_dot_v = std::sqrt(0.5f);

}  // namespace

// "estimate": E = Sum(power) / (pi r^2) over the k returned, r the farthest; the term is E (n.v),
// kd not applied again; only with more than 50 photons in the map and Y(kd) > 0.2.
TEST(ClassicEstimate, CausticTermAndItsGates) {
    const glm::vec3 power(0.001f, 0.002f, 0.003f);
    const glm::vec3 e = 5.0f * power / (pi * 0.05f * 0.05f);
    FloorView bright(0.5);
    const PhotonMap many = photons_around_origin(51, power);
    bright.setup.caustic_map = &many;
    const glm::vec3 c = bright.colour();
    EXPECT_NEAR(c.x, e.x * n_dot_v, 1e-4f);
    EXPECT_NEAR(c.y, e.y * n_dot_v, 1e-4f);
    EXPECT_NEAR(c.z, e.z * n_dot_v, 1e-4f);
    const PhotonMap fifty = photons_around_origin(50, power);
    bright.setup.caustic_map = &fifty;
    EXPECT_EQ(bright.colour(), glm::vec3(0.0f)) << "50 photons: no caustic term";
    FloorView dull(0.2);  // Y(kd) = 0.2 is not above 0.2
    dull.setup.caustic_map = &many;
    EXPECT_EQ(dull.colour(), glm::vec3(0.0f));
}

// "search": the search always returns k photons: far ones make a wide, dim disc, not nothing.
TEST(ClassicEstimate, FarPhotonsStillCount) {
    std::vector<Photon> photons;
    for (int i = 0; i < 60; ++i) photons.push_back({glm::vec3(1.0f + 0.1f * static_cast<float>(i), 0, 0), glm::vec3(1.0f), glm::vec3(0, -1, 0)});
    const PhotonMap far(std::move(photons));
    FloorView view(0.5);
    view.setup.caustic_map = &far;
    const float r = 1.4f;  // the fifth nearest
    EXPECT_NEAR(view.colour().x, 5.0f / (pi * r * r) * n_dot_v, 1e-4f);
}

// "GI term": the GI estimate replaces the ambient term: A = kd E_gi (n.v).
TEST(ClassicEstimate, GiReplacesTheAmbient) {
    const glm::vec3 power(0.001f);
    FloorView view(0.5);
    view.setup.ambient = glm::vec3(0.3f);
    EXPECT_NEAR(view.colour().x, 0.15f, 1e-6f) << "without GI: A kd";
    const PhotonMap gi = photons_around_origin(20, power);
    view.setup.gi_map = &gi;
    view.params.gi_neighbours = 5;
    const float e = 5.0f * 0.001f / (pi * 0.05f * 0.05f);
    EXPECT_NEAR(view.colour().x, 0.5f * e * n_dot_v, 1e-5f);
}

// "debug views": --draw-caustics-only shows the raw E (no n.v) where Y(kd) > 0.2 and black
// elsewhere; --draw-gi-only the same on the GI map.
TEST(ClassicDebugViews, EstimateOnlyViews) {
    const glm::vec3 power(0.001f, 0.002f, 0.003f);
    const PhotonMap many = photons_around_origin(51, power);
    FloorView view(0.5);
    view.setup.ambient = glm::vec3(1.0f);  // not shown
    view.setup.caustic_map = &many;
    view.setup.draw_caustics_only = true;
    EXPECT_NEAR(view.colour().z, 5.0f * 0.003f / (pi * 0.05f * 0.05f), 1e-4f);
    FloorView dull(0.2);
    dull.setup.ambient = glm::vec3(1.0f);
    dull.setup.caustic_map = &many;
    dull.setup.draw_caustics_only = true;
    EXPECT_EQ(dull.colour(), glm::vec3(0.0f));
    FloorView gi(0.5);
    gi.setup.gi_map = &many;
    gi.params.gi_neighbours = 5;
    gi.setup.draw_gi_only = true;
    EXPECT_NEAR(gi.colour().y, 5.0f * 0.002f / (pi * 0.05f * 0.05f), 1e-4f);
}

// "debug views": --draw-caustic-map shows the nearest photon within 0.01 world units, normalised to
// unit length; black beyond it and where Y(kd) < 0.2. --draw-gi-map the same on the GI map.
TEST(ClassicDebugViews, PhotonDotViews) {
    const glm::vec3 power(0.3f, 0.4f, 0.0f);
    const PhotonMap near = photons_around_origin(10, power, 0.005f);
    const PhotonMap far = photons_around_origin(10, power, 0.02f);
    for (bool gi : {false, true}) {
        FloorView view(0.5);
        view.setup.ambient = glm::vec3(1.0f);
        (gi ? view.setup.draw_gi_map : view.setup.draw_caustic_map) = true;
        (gi ? view.setup.gi_map : view.setup.caustic_map) = &near;
        const glm::vec3 dot = view.colour();
        EXPECT_NEAR(dot.x, 0.6f, 1e-6f);
        EXPECT_NEAR(dot.y, 0.8f, 1e-6f);
        EXPECT_EQ(dot.z, 0.0f);
        (gi ? view.setup.gi_map : view.setup.caustic_map) = &far;
        EXPECT_EQ(view.colour(), glm::vec3(0.0f)) << "nearest at 0.02: black";
        FloorView dull(0.1);
        (gi ? dull.setup.draw_gi_map : dull.setup.draw_caustic_map) = true;
        (gi ? dull.setup.gi_map : dull.setup.caustic_map) = &near;
        EXPECT_EQ(dull.colour(), glm::vec3(0.0f)) << "Y(kd) < 0.2: black";
    }
}

// Photons and estimate end to end: the virtual-light scene (a point light over a mirror of ks 0.9,
// its direct light blocked, a ceiling of kd 0.8 lit only through the mirror). A photon reaching the
// ceiling chose specular at the mirror with P = Y(ks) and kept power ks, not ks / P, and is stored
// with power x kd: the caustic term is
//   (shot / N) Y(ks) ks kd C d_u^2 cos(theta) / (c2 d^2) x (n.v),
// d and theta from the mirror image of the light, shot / N the emission cells' shortfall (at
// N = 24 M each cell holds about 18 photons, so the floor's loss is nearly uniform over the sky).
TEST(ClassicTransport, VirtualLightCausticMatchesTheClosedForm) {
    JobBuilder b = caustica::testing::virtual_light_scene(false);
    const long long n = 24'000'000;
    b.job.options.caustic_num_photons = n;
    b.job.options.caustic_num_neighbours = 200;
    b.job.options.integrator = IntegratorKind::classic;
    b.job.ambient = {0, 0, 0};
    const RenderJob job = b.build();
    const Image image = caustica::testing::render(job);
    const double shot = static_cast<double>(classic_photons_offered(n)) / static_cast<double>(n);
    const double ks = 0.9, luma_ks = 0.9, kd = 0.8;
    const Camera camera(job.camera, job.width, job.height);
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
    double sum_ratio = 0.0;
    int count = 0;
    for (std::size_t index : caustica::testing::virtual_light_annulus(job)) {
        const int x = static_cast<int>(index % job.width), y = static_cast<int>(index / job.width);
        const Ray ray = camera.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        SurfaceHit hit;
        if (!scene.intersect(ray, hit) || std::fabs(hit.position.y - 2.95f) > 1e-3f) continue;  // the blocker hides it
        const float t = (2.95f - ray.origin.y) / ray.direction.y;
        const glm::dvec3 p = glm::dvec3(ray.origin + t * ray.direction);
        const glm::dvec3 to_image = p - glm::dvec3(0, -1, 0);
        const double d2 = glm::dot(to_image, to_image);
        const double cos_theta = to_image.y / std::sqrt(d2);
        const double n_dot_v = glm::normalize(ray.direction).y;  // the ceiling's normal is -y, v = -direction
        const double expected = shot * luma_ks * ks * kd * cos_theta / d2 * n_dot_v;
        sum_ratio += image.pixels[index].x / expected;
        ++count;
    }
    ASSERT_GT(count, 500);
    std::printf("classic virtual light: %d pixels, mean ratio to the closed form %.4f\n", count, sum_ratio / count);
    // The k-nearest estimate over 200 photons has ~7% noise per pixel and a small bias on this
    // smooth density; the mean over the annulus's ~1000 pixels is within 3%. Without the
    // uncompensated odds it would be 1/0.9 too bright, without n.v 15-40%, without the
    // shortfall 1/0.84.
    EXPECT_NEAR(sum_ratio / count, 1.0, 0.03);
}

// The preview switches integrator live: the BVH stays, the photon stage and the image are redone.
TEST(ClassicTransport, SwitchingIntegratorKeepsTheSceneAndRedoesThePhotons) {
    JobBuilder b = caustica::testing::virtual_light_scene(false);
    b.job.options.caustic_num_photons = 200'000;
    RenderSession session;
    RenderJob job = b.build();
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    const Image classic = session.image();
    job.options.integrator = IntegratorKind::progressive;
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    const RenderSession::StageCounters c = session.stage_counters();
    EXPECT_EQ(c.scene_builds, 1);
    EXPECT_EQ(c.photon_passes, 2);
    EXPECT_EQ(c.renders, 2);
    EXPECT_EQ(session.stats().integrator, "progressive");
    EXPECT_NE(session.image().pixels, classic.pixels);
}


// The classic projection map only saves time: the classic pass skips whole emission cells the map
// cannot reach (and then single directions), and stores exactly the photons it stores without it.
TEST(ClassicTransport, ProjectionMapSkipsCellsWithoutChangingThePhotons) {
    JobBuilder b = caustica::testing::virtual_light_scene(false);
    b.job.options.caustic_num_photons = 3'000'000;
    const auto photons = [&](ProjectionMapMode mode, long long& traced) {
        b.job.options.projection_map = mode;
        const RenderJob job = b.build();
        const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
        CausticStage stage;
        build_caustic_stage(stage, scene, job, nullptr);
        traced = stage.lights.at(0).traced;
        std::vector<std::array<float, 6>> out;
        for (std::size_t i = 0; i < stage.map->size(); ++i) {
            const Photon& p = stage.map->photon(i);
            out.push_back({p.position.x, p.position.y, p.position.z, p.power.x, p.power.y, p.power.z});
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    long long traced_on = 0, traced_off = 0;
    const auto on = photons(ProjectionMapMode::on, traced_on);
    const auto off = photons(ProjectionMapMode::off, traced_off);
    EXPECT_GT(on.size(), 10000u);
    EXPECT_EQ(on, off);
    EXPECT_LT(traced_on, traced_off / 2);  // the map kept the directions towards the mirror only
}

// The original accepts --draw-caustic-prm and renders exactly as without it; scenes set it.
TEST(ClassicDebugViews, DrawCausticPrmChangesNothingAndShowProjectionMapTints) {
    for (const char* integrator : {"classic", "progressive"}) {
        const std::string scene = std::string(R"(
gr.option('--integrator )") + integrator + R"( --caustic-num-photons 200000')
glass = gr.material({0, 0, 0}, {0.9, 0.9, 0.9}, 20)
glass:set_ri(1.5)
ball = gr.nh_sphere('ball', {0, 1, 0}, 1)
ball:set_material(glass)
floor = gr.cube('floor')
floor:translate(0, -1, 0)
floor:scale(10, 1, 10)
floor:set_material(gr.material({0.8, 0.8, 0.8}, {0, 0, 0}, 0))
root = gr.node('root')
root:add_child(floor)
root:add_child(ball)
)";
        const std::string render = "gr.render(root, 'x.png', 24, 24, {0, 4, 6}, {0, -4, -6}, {0, 1, 0}, 40, {0.2, 0.2, 0.2}, "
                                   "{gr.light({2, 6, 1}, {1, 1, 1}, {0, 0, 0.05})})\n";
        const Image plain = caustica::testing::render(caustica::testing::load_first_job(scene + render));
        const Image flagged = caustica::testing::render(caustica::testing::load_first_job(scene + "gr.option('--draw-caustic-prm')\n" + render));
        ASSERT_EQ(plain.width, flagged.width);
        for (int y = 0; y < plain.height; ++y)
            for (int x = 0; x < plain.width; ++x)
                ASSERT_EQ(std::memcmp(&plain.at(x, y), &flagged.at(x, y), sizeof(glm::vec3)), 0)
                    << integrator << " " << x << "," << y;
        // Our own flag does tint what the projection maps aim at.
        const Image shown = caustica::testing::render(caustica::testing::load_first_job(scene + "gr.option('--show-projection-map')\n" + render));
        int differ = 0;
        for (int y = 0; y < plain.height; ++y)
            for (int x = 0; x < plain.width; ++x) differ += plain.at(x, y) != shown.at(x, y);
        EXPECT_GT(differ, 0) << integrator;
    }
}

namespace {

/// Light at the centre of a closed sphere of radius 1 whose inside is diffuse grey `rho`.
std::string sphere_room(double rho) {
    char text[1024];
    std::snprintf(text, sizeof text, R"(
gr.option('--gi --gi-num-photons 2621440')
room = gr.sphere('room')
room:set_material(gr.material({%.17g, %.17g, %.17g}, {0, 0, 0}, 0))
root = gr.node('root')
root:add_child(room)
gr.render(root, 'x.png', 4, 4, {0, 0, 0.5}, {0, 0, -1}, {0, 1, 0}, 30, {0, 0, 0},
          {gr.light({0, 0, 0}, {1, 1, 1}, {0, 0, 1})})
)",
                  rho, rho, rho);
    return text;
}

/// The share of the emitted energy the GI map stores in a closed diffuse sphere with the light at
/// its centre, by the classic rules: a photon hits the wall at normal incidence, chooses diffuse
/// with P = rho (power x rho, not divided by P) and leaves at angle alpha from the mirror
/// direction, sin alpha uniform; every later hit stores power x rho, and hits 1..13 are all it
/// makes. In a sphere the next hit's incidence equals the leaving angle, so only the angle to the
/// normal matters: cos b' = cos a cos b + sin a sin b cos phi. A direction with cos b' < 0 leaves
/// the sphere (`clipped`: mirrored back in). Integrated here by an independent Monte Carlo.
double gi_share(double rho, bool clipped) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int chains = 400000;
    std::vector<double> alive(14, 0.0);  // alive[k]: chains whose path reaches hit k (k >= 2)
    for (int c = 0; c < chains; ++c) {
        double cos_b = std::sqrt(1.0 - std::pow(u(rng), 2.0));  // first bounce about the normal
        alive[2] += 1.0;
        for (int k = 3; k <= 13; ++k) {
            const double sin_a = u(rng), phi = 2.0 * pi * u(rng);
            const double cos_a = std::sqrt(1.0 - sin_a * sin_a), sin_b = std::sqrt(std::max(0.0, 1.0 - cos_b * cos_b));
            double next = cos_a * cos_b + sin_a * sin_b * std::cos(phi);
            if (next < 0.0) {
                if (!clipped) break;
                next = -next;
            }
            cos_b = next;
            alive[k] += 1.0;
        }
    }
    // Hit k >= 2 is reached after k - 1 diffuse choices (odds rho each) and stores rho^k.
    double share = 0.0;
    for (int k = 2; k <= 13; ++k) share += alive[k] / chains * std::pow(rho, k - 1) * std::pow(rho, k);
    return share;
}

}  // namespace

// "The GI lobe is not clipped": in a closed grey sphere around the light, the GI map's stored
// power, and the GI estimate anywhere on the wall (the photons lie evenly: total over 4 pi R^2),
// follow the unclipped lobe; turning directions back would keep several percent more.
TEST(ClassicGlobalIllumination, AClosedRoomLosesWhatTheUnclippedLobeSendsIntoTheWall) {
    const double rho = 0.8;
    const RenderJob job = caustica::testing::load_first_job(sphere_room(rho));
    ClassicPhotonSettings s;
    s.gi_photons = job.options.gi_num_photons;
    s.seed = 9;
    const ClassicPhotonResult r = shoot_classic_photons(RenderScene(*job.scene, flatten_scene(*job.scene, job.root, false)), nullptr, job_lights(job), s, nullptr);
    const double energy = 4.0 * pi / static_cast<double>(s.gi_photons);  // per photon, C = c2 = d_u = 1
    const double shot = static_cast<double>(classic_photons_offered(s.gi_photons));
    double total = 0.0;
    for (const Photon& p : r.gi) total += p.power.x;
    const double measured = total / (shot * energy);
    const double unclipped = gi_share(rho, false), clipped = gi_share(rho, true);
    std::printf("GI stored share: %.4f measured, %.4f unclipped lobe, %.4f clipped\n", measured, unclipped, clipped);
    EXPECT_NEAR(measured, unclipped, 0.005 * unclipped);
    EXPECT_GT(clipped / unclipped, 1.03);  // the two rules are told apart

    // The estimate over 100 neighbours, averaged over points of the wall, is that power spread
    // evenly over the sphere's area.
    PhotonMap map(r.gi);
    std::vector<Neighbour> scratch(100);
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    double sum = 0.0;
    const int points = 400;
    for (int i = 0; i < points; ++i) {
        const glm::vec3 p = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        sum += map.classic_estimate(p, 100, 0.15f, scratch.data()).value.x;
    }
    const double expected = unclipped * shot * energy / (4.0 * pi);
    std::printf("GI estimate on the wall: %.5f, expected %.5f\n", sum / points, expected);
    EXPECT_NEAR(sum / points, expected, 0.03 * expected);
}
