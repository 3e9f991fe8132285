// Caustics: the k-D tree against brute force, the energy rule and radiance estimate against
// closed forms, and the virtual-light test of the whole photon pipeline.
#include "core/scene/camera.h"
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/photon_kdtree.h"
#include "core/photons/photon_map.h"
#include "core/photons/photon_tracer.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/source_location.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>

using namespace caustica;
using caustica::testing::JobBuilder;
using caustica::testing::virtual_light_scene;

namespace {

constexpr float pi = 3.14159265358979f;

/// Points clustered on a few planes and spheres, like a caustic map.
std::vector<glm::vec3> clustered_points(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> points(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float a = u(rng), b = u(rng);
        switch (i % 3) {
            case 0: points[i] = {a * 4.0f - 2.0f, 0.0f, b * 4.0f - 2.0f}; break;             // floor
            case 1: points[i] = {0.3f * std::cos(6.28f * a), 0.0f, 0.3f * std::sin(6.28f * a) + 0.05f * b}; break;  // ring
            default: points[i] = {0.2f * a, 0.001f * b, 0.2f * u(rng)}; break;                // bright spot
        }
    }
    return points;
}

std::vector<float> brute_force(const std::vector<glm::vec3>& points, glm::vec3 q, std::size_t k, float max_distance) {
    std::vector<float> d2;
    for (const glm::vec3& p : points) {
        const float d = glm::dot(p - q, p - q);
        if (d < max_distance * max_distance) d2.push_back(d);
    }
    std::sort(d2.begin(), d2.end());
    if (d2.size() > k) d2.resize(k);
    return d2;
}

}  // namespace

TEST(KdTree, MatchesBruteForce) {
    const std::vector<glm::vec3> points = clustered_points(20000, 1);
    const PhotonKdTree tree(points);
    ASSERT_EQ(tree.size(), points.size());
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    std::vector<Neighbour> result(200);
    for (int query = 0; query < 200; ++query) {
        const glm::vec3 q(u(rng) * 0.5f, u(rng) * 0.01f, u(rng) * 0.5f);
        for (std::uint32_t k : {1u, 10u, 200u}) {
            for (float max_distance : {0.01f, 0.1f, 10.0f}) {
                const std::uint32_t found = tree.nearest(q, k, max_distance, result.data());
                std::vector<float> got;
                for (std::uint32_t i = 0; i < found; ++i) {
                    got.push_back(result[i].distance2);
                    const glm::vec3 p = tree.points()[result[i].index];  // index is in tree order
                    EXPECT_FLOAT_EQ(glm::dot(p - q, p - q), result[i].distance2);
                    EXPECT_EQ(p, points[tree.order()[result[i].index]]);
                }
                std::sort(got.begin(), got.end());
                ASSERT_EQ(got, brute_force(points, q, k, max_distance)) << "k " << k << " max " << max_distance;
            }
        }
    }
}

TEST(KdTree, DegenerateInputs) {
    std::vector<Neighbour> result(64);
    EXPECT_EQ(PhotonKdTree(std::vector<glm::vec3>{}).nearest({0, 0, 0}, 10, 1.0f, result.data()), 0u);
    // All photons at one point: every query finds them, at distance 0 when on the spot.
    const PhotonKdTree same(std::vector<glm::vec3>(1000, glm::vec3(1, 2, 3)));
    EXPECT_EQ(same.nearest({1, 2, 3}, 50, 0.1f, result.data()), 50u);
    EXPECT_EQ(result[0].distance2, 0.0f);
    EXPECT_EQ(same.nearest({1, 2, 3.2f}, 50, 0.1f, result.data()), 0u);  // out of reach
    // k larger than the photons stored.
    const PhotonKdTree few(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    EXPECT_EQ(few.nearest({0, 0, 0}, 64, 10.0f, result.data()), 3u);
}

TEST(EnergyRule, MatchesTheSeedFormula) {
    Light light;
    light.colour = {0.5f, 1.0f, 2.0f};
    light.falloff = {0.0f, 0.0f, 2.0f};
    const glm::vec3 e = photon_energy(light, 3.0, 1000, 1.5);
    // E = 4 pi d_u^2 C / (f P) x fudge
    EXPECT_NEAR(e.y, 4.0f * pi * 9.0f * 1.0f / (2.0f * 1000.0f) * 1.5f, 1e-6f);
    EXPECT_NEAR(e.x / e.y, 0.5f, 1e-6f);
}

TEST(Roulette, SeedProbabilities) {
    Material m;
    m.kd = glm::vec3(0.3f);
    m.ks = glm::vec3(0.1f);
    m.reflective = true;
    const RouletteOdds odds = roulette_odds(m);
    EXPECT_NEAR(odds.diffuse, 0.3f, 1e-6f);   // the original's example: 0.9 / 3
    EXPECT_NEAR(odds.specular, 0.1f, 1e-6f);  // 0.3 / 3
    m.reflective = false;                     // a Phong highlight is not a specular interaction
    EXPECT_EQ(roulette_odds(m).specular, 0.0f);
}

TEST(RadianceEstimate, UniformDensityGivesPowerOverArea) {
    // Photons on a grid of spacing h in the plane z = 0, each of power p, arriving from +z.
    const float h = 0.01f, p = 0.002f;
    std::vector<Photon> photons;
    for (int i = -100; i <= 100; ++i)
        for (int j = -100; j <= 100; ++j) photons.push_back({{i * h, j * h, 0.0f}, glm::vec3(p), {0, 0, -1}});
    const PhotonMap map(std::move(photons));
    std::vector<Neighbour> scratch(400);
    const float expected = p / (h * h);
    for (int k : {50, 100, 400}) {
        const glm::vec3 e = map.estimate({0.0013f, -0.0021f, 0.0f}, {0, 0, 1}, k, 1.0f, PhotonFilter::none, scratch.data());
        EXPECT_NEAR(e.x / expected, 1.0f, 0.08f) << k;  // the grid's discreteness at small k
        const glm::vec3 c = map.estimate({0.0013f, -0.0021f, 0.0f}, {0, 0, 1}, k, 1.0f, PhotonFilter::cone, scratch.data());
        EXPECT_NEAR(c.x / expected, 1.0f, 0.08f) << k;
    }
    // Photons arriving from the back side do not count.
    EXPECT_EQ(map.estimate({0, 0, 0}, {0, 0, -1}, 100, 1.0f, PhotonFilter::none, scratch.data()), glm::vec3(0.0f));
}

TEST(RadianceEstimate, FewerThanNPhotonsUseTheSearchDisc) {
    const PhotonMap map(std::vector<Photon>{{{0, 0, 0}, glm::vec3(1.0f), {0, -1, 0}}});
    std::vector<Neighbour> scratch(100);
    const glm::vec3 e = map.estimate({0.01f, 0, 0}, {0, 1, 0}, 100, 0.5f, PhotonFilter::none, scratch.data());
    EXPECT_NEAR(e.x, 1.0f / (pi * 0.25f), 1e-5f);  // not 1 / (pi 0.01^2): no hot spot
    EXPECT_NEAR(map.estimate({0, 0, 0}, {0, 1, 0}, 1, 0.5f, PhotonFilter::none, scratch.data()).x, 0.0f, 0.0f)
        << "N = 1 on top of the photon: a zero-area disc gives no estimate rather than infinity";
}

namespace {

/// Mean red value over the annulus of virtual_light_annulus.
double annulus_mean(const Image& image, const RenderJob& job, double scale) {
    double sum = 0.0;
    const std::vector<std::size_t> pixels = caustica::testing::virtual_light_annulus(job, scale);
    for (std::size_t i : pixels) sum += image.pixels[i].x;
    return sum / static_cast<double>(pixels.size());
}

}  // namespace

TEST(VirtualLight, MirrorCausticMatchesALightAtTheMirroredPosition) {
    JobBuilder reference = virtual_light_scene(true);
    reference.job.options.integrator = IntegratorKind::progressive;
    const RenderJob reference_job = reference.build();
    const double expected = annulus_mean(caustica::testing::render(reference_job), reference_job, 1.0);
    EXPECT_GT(expected, 0.02);
    for (ProjectionMapMode mode : {ProjectionMapMode::on, ProjectionMapMode::off}) {
        JobBuilder b = virtual_light_scene(false);
        b.job.options.integrator = IntegratorKind::progressive;  // these tests are of its photon map
        b.job.options.caustic_num_photons = 1'000'000;
        b.job.options.caustic_num_neighbours = 100;
        b.job.options.caustic_max_dist = 0.3;
        b.job.options.projection_map = mode;
        b.job.options.draw_caustics_only = true;
        const RenderJob job = b.build();
        const double mean = annulus_mean(caustica::testing::render(job), job, 1.0);
        std::printf("virtual light: reference %.5f, photons %.5f (ratio %.4f)\n", expected, mean, mean / expected);
        // Tolerance: the N/(N-1) bias of the k-th-neighbour disc (1%) plus noise averaged over
        // ~1000 pixels (under 1%): 3%.
        EXPECT_NEAR(mean / expected, 1.0, 0.03) << (mode == ProjectionMapMode::on ? "map on" : "map off");
    }
}

TEST(VirtualLight, ScaledSceneWithScaledUnitDistanceGivesTheSameCaustics) {
    double means[3];
    int i = 0;
    for (double scale : {1e-3, 1.0, 1e4}) {
        JobBuilder b = virtual_light_scene(false, scale);
        b.job.options.integrator = IntegratorKind::progressive;  // these tests are of its photon map
        b.job.options.caustic_num_photons = 200'000;
        b.job.options.draw_caustics_only = true;
        const RenderJob job = b.build();
        means[i++] = annulus_mean(caustica::testing::render(job), job, scale);
    }
    std::printf("scale: %.6f %.6f %.6f\n", means[0], means[1], means[2]);
    EXPECT_NEAR(means[0] / means[1], 1.0, 0.01);
    EXPECT_NEAR(means[2] / means[1], 1.0, 0.01);
}

TEST(Photons, ReproducibleForAnyThreadCount) {
    JobBuilder b = virtual_light_scene(false);
    const RenderJob job = b.build();
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
    PhotonPassSettings settings;
    settings.photons_per_light = 50'000;
    auto shoot = [&](int threads) {
        tbb::task_arena arena(threads);
        PhotonPassResult r;
        arena.execute([&] { r = shoot_caustic_photons(scene, job_lights(job), settings, nullptr); });
        return r;
    };
    const PhotonPassResult one = shoot(1), two = shoot(2);
    ASSERT_EQ(one.photons.size(), two.photons.size());
    ASSERT_GT(one.photons.size(), 1000u);
    for (std::size_t i = 0; i < one.photons.size(); ++i) {
        ASSERT_EQ(one.photons[i].position, two.photons[i].position);
        ASSERT_EQ(one.photons[i].power, two.photons[i].power);
    }
}

TEST(Photons, ZeroOneAndRefusedCounts) {
    JobBuilder b = virtual_light_scene(false);
    b.job.options.caustic_num_photons = 0;
    EXPECT_FALSE(caustics_needed(b.build()));
    b.job.options.caustic_num_photons = 1;
    const Image one = caustica::testing::render(b.build());  // one photon: no crash, no NaN
    for (const glm::vec3& p : one.pixels) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    b.job.options.caustic_num_photons = 100'000'000'000LL;
    RenderSession session;
    session.set_job(b.build());
    session.start();
    try {
        session.wait();
        FAIL() << "expected a refusal";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--caustic-num-photons 100000000000"), std::string::npos) << e.what();
    }
}

TEST(Photons, MemoryCheckCountsOnlyWhatTheMapsLetThrough) {
    EXPECT_NO_THROW(check_photon_memory(1e6, 1'000'000'000, 1e9));  // 1e9 directions, 1e6 through the map
    EXPECT_THROW(check_photon_memory(1e8, 1'000'000'000, 1e9), InputError);
    EXPECT_GT(photon_memory_bound(1e6), 36e6);  // at least the photons themselves
}

TEST(ProjectionMap, RowRangesSkipEmptyBands) {
    ProjectionMap map(90);
    map.set_cell(45, 10, true);  // a row at the equator: u around 0.5
    EXPECT_TRUE(map.any_occupied_between(0.49, 0.51));
    EXPECT_FALSE(map.any_occupied_between(0.0, 0.3));
    EXPECT_FALSE(map.any_occupied_between(0.7, 1.2));  // wraps round to 0.2
    EXPECT_TRUE(map.any_occupied_between(0.9, 1.6));   // wraps round past 0.5
}

TEST(Photons, NoSpecularObjectMeansNoPhotonPass) {
    JobBuilder b(16, 16);
    b.add(NodeKind::sphere, b.material({0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, 10));  // highlight, not a mirror
    b.light({0, 3, 0}, {1, 1, 1}, {0, 0, 1});
    b.job.options.caustic_num_photons = 1000;
    EXPECT_FALSE(caustics_needed(b.build()));
}

TEST(Photons, LightWithoutQuadraticFalloffWarnsAndShootsNothing) {
    JobBuilder b = virtual_light_scene(false);
    b.scene->lights[0].falloff = {1, 0, 0};
    b.job.options.caustic_num_photons = 10'000;
    RenderSession session;
    session.set_job(b.build());
    session.start();
    ASSERT_TRUE(session.wait());
    bool warned = false;
    for (const std::string& w : session.warnings()) warned |= w.find("no quadratic falloff") != std::string::npos;
    EXPECT_TRUE(warned);
    EXPECT_EQ(session.stats().caustic_photons, 0u);
}

TEST(Photons, LightInsideAGlassSphereStillMakesCaustics) {
    JobBuilder b(16, 16);
    b.job.options.integrator = IntegratorKind::progressive;  // these tests are of its photon map
    const int floor = b.add(NodeKind::cube, b.material({0.8, 0.8, 0.8}));
    b.translate(floor, {0, -2, 0});
    b.scale(floor, {5, 0.1, 5});
    MaterialDesc glass;
    glass.ks = glm::dvec3(0.9);
    glass.refractive_index = 1.5;
    b.scene->materials.push_back(glass);
    b.add(NodeKind::sphere, static_cast<int>(b.scene->materials.size()) - 1);
    b.light({0, 0, 0}, {1, 1, 1}, {0, 0, 1});
    b.job.options.caustic_num_photons = 20'000;
    RenderSession session;
    session.set_job(b.build());
    session.start();
    ASSERT_TRUE(session.wait());
    const RenderStats stats = session.stats();
    ASSERT_EQ(stats.caustic_lights.size(), 1u);
    EXPECT_FALSE(stats.caustic_lights[0].projection_map_used);  // every direction is occupied
    EXPECT_GT(stats.caustic_photons, 1000u);
}

TEST(Photons, SpecularMaterialThatGainsEnergyIsRefusedWithItsLine) {
    JobBuilder b = virtual_light_scene(false);
    b.job.options.integrator = IntegratorKind::progressive;  // these tests are of its photon map
    b.scene->materials[2].kd = {0.5, 0.5, 0.5};  // the mirror: mean kd 0.5 + mean ks 0.9 > 1
    b.scene->materials[2].where = {"scene.lua", 4};
    b.job.options.caustic_num_photons = 1000;
    RenderSession session;
    session.set_job(b.build());
    session.start();
    try {
        session.wait();
        FAIL() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("scene.lua:4: gr.material:", 0), 0u) << e.what();
    }
}

namespace {

/// Renders `job` to its end in `session`, which keeps its stages between jobs.
void render_in(RenderSession& session, const RenderJob& job) {
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
}

}  // namespace

TEST(Session, OnlyWhatAChangeInvalidatesIsRedone) {
    JobBuilder b = virtual_light_scene(false);
    b.job.options.caustic_num_photons = 20'000;
    RenderJob job = b.build();
    RenderSession session;
    auto run = [&](const RenderJob& j) { render_in(session, j); };
    run(job);
    job.options.caustic_num_neighbours = 20;  // re-gathers, no re-shoot
    job.options.caustic_max_dist = 0.2;
    run(job);
    job.camera.eye = {0.1, 0.5, 0};           // camera: neither BVH nor photons
    run(job);
    EXPECT_EQ(session.stage_counters().scene_builds, 1);
    EXPECT_EQ(session.stage_counters().photon_passes, 1);
    EXPECT_EQ(session.stage_counters().renders, 3);
    job.options.caustic_num_photons = 30'000;  // re-shoot, no BVH rebuild
    run(job);
    EXPECT_EQ(session.stage_counters().scene_builds, 1);
    EXPECT_EQ(session.stage_counters().photon_passes, 2);
}

TEST(Session, PhotonsPerPixelMakeTheImageSizeAPhotonCount) {
    // With --photons-per-pixel the first pass's photons depend on the image's size: a new size
    // shoots them again, where without the option it keeps them.
    for (const double per_pixel : {0.0, 1.0}) {
        SCOPED_TRACE(per_pixel);
        JobBuilder b = virtual_light_scene(false);
        b.job.options.integrator = IntegratorKind::progressive;
        b.job.options.caustic_num_photons = 2'000;
        b.job.options.photons_per_pixel = per_pixel;
        b.job.options.passes = 2;
        RenderJob job = b.build();
        RenderSession session;
        auto run = [&](const RenderJob& j) { render_in(session, j); };
        run(job);
        job.width = job.height = 40;
        run(job);
        EXPECT_EQ(session.stage_counters().photon_passes, per_pixel > 0.0 ? 2 : 1);
    }
}

TEST(Convergence, ErrorFallsAsPhotonsGrow) {
    JobBuilder reference = virtual_light_scene(true);
    reference.job.options.integrator = IntegratorKind::progressive;
    const RenderJob reference_job = reference.build();
    const Image truth = caustica::testing::render(reference_job);
    double previous = 1e9;
    for (long long photons : {10'000LL, 100'000LL, 1'000'000LL}) {
        JobBuilder b = virtual_light_scene(false);
        b.job.options.integrator = IntegratorKind::progressive;  // these tests are of its photon map
        b.job.options.caustic_num_photons = photons;
        b.job.options.caustic_num_neighbours = 50;
        b.job.options.draw_caustics_only = true;
        const RenderJob job = b.build();
        const Image image = caustica::testing::render(job);
        double squared = 0.0;
        const std::vector<std::size_t> pixels = caustica::testing::virtual_light_annulus(job);
        for (std::size_t i : pixels) squared += std::pow(image.pixels[i].x - truth.pixels[i].x, 2.0);
        const int count = static_cast<int>(pixels.size());
        const double rmse = std::sqrt(squared / count);
        std::printf("convergence: %lld photons, rmse %.5f\n", photons, rmse);
        EXPECT_LT(rmse, previous * 0.8) << photons;  // 10x photons must cut the error clearly
        previous = rmse;
    }
}

TEST(ProjectionMap, CellLookupFromUvAgreesWithTheDirection) {
    ProjectionMap map(37);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> coin(0, 1);
    for (int r = 0; r < map.rows(); ++r)
        for (int c = 0; c < map.columns(); ++c) map.set_cell(r, c, coin(rng));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int mismatches = 0;
    for (int i = 0; i < 100000; ++i) {
        const float a = u(rng), b = u(rng);
        const float y = 1.0f - 2.0f * a, s = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const glm::vec3 d(s * std::cos(6.2831853f * b), y, s * std::sin(6.2831853f * b));
        mismatches += map.occupied_uv(a, b) != map.occupied(d);
    }
    EXPECT_LE(mismatches, 20);  // only where float rounding puts a direction on a cell border
}

TEST(ProjectionMap, OccupiedFractionUsesTrueCellAreas) {
    ProjectionMap map(90);
    for (int c = 0; c < map.columns(); ++c) map.set_cell(0, c, true);  // the polar cap theta < 2 degrees
    const double cap = 0.5 * (1.0 - std::cos(3.14159265358979 / 90.0));
    EXPECT_NEAR(map.occupied_fraction(), cap, 1e-9);
    for (int r = 0; r < map.rows() / 2; ++r)
        for (int c = 0; c < map.columns(); ++c) map.set_cell(r, c, true);
    EXPECT_NEAR(map.occupied_fraction(), 0.5, 1e-9);  // the upper hemisphere
}

namespace {

/// The summed power of a pass's stored photons (mean of the channels).
double stored_power(const PhotonPassResult& r) {
    double sum = 0.0;
    for (const Photon& p : r.photons) sum += (static_cast<double>(p.power.x) + p.power.y + p.power.z) / 3.0;
    return sum;
}

}  // namespace

TEST(Photons, AMinimumTracedCountRaisesTheDirectionsAndKeepsTheEnergy) {
    JobBuilder b = virtual_light_scene(false);
    const RenderJob job = b.build();
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
    PhotonPassSettings settings;
    settings.projection_map = ProjectionMapMode::on;
    settings.photons_per_light = 200'000;
    const PhotonPassResult given = shoot_caustic_photons(scene, job_lights(job), settings, nullptr);
    const LightPhotonReport& g = given.lights[0];
    ASSERT_TRUE(g.projection_map_used);
    ASSERT_GT(g.occupied_fraction, 0.25);  // 50 000 traced below need fewer than 200 000 directions
    ASSERT_LT(g.occupied_fraction, 0.9);  // the map rejects directions: the count must grow past the minimum
    EXPECT_EQ(g.candidates, 200'000);

    // 1 000 directions asked, 50 000 traced at least: the directions become 50 000 over the
    // occupied fraction, every one of them traced (to the rounding of the cells' shares), and each
    // photon carries the energy of one direction of the raised count, so the light's power is
    // what 200 000 directions deliver (the roulette's noise at 45 000 stored photons: ~0.2%).
    settings.photons_per_light = 1'000;
    settings.min_traced_per_light = 50'000;
    std::atomic<long long> progress{0};
    settings.progress = &progress;
    const PhotonPassResult raised = shoot_caustic_photons(scene, job_lights(job), settings, nullptr);
    const LightPhotonReport& r = raised.lights[0];
    EXPECT_EQ(progress.load(), 1'000);  // progress counts the directions given, what the session's total holds
    EXPECT_EQ(r.candidates, static_cast<long long>(std::ceil(50'000 / r.occupied_fraction)));
    EXPECT_GE(r.traced, 49'999);
    EXPECT_LE(r.traced, 50'002);
    EXPECT_NEAR(stored_power(raised) / stored_power(given), 1.0, 0.01);

    // A count that already traces more is kept.
    settings.photons_per_light = 200'000;
    EXPECT_EQ(shoot_caustic_photons(scene, job_lights(job), settings, nullptr).lights[0].candidates, 200'000);

    // Without a map every direction is traced: the minimum is the count.
    settings.projection_map = ProjectionMapMode::off;
    settings.photons_per_light = 1'000;
    settings.min_traced_per_light = 30'000;
    progress = 0;
    const PhotonPassResult unmapped = shoot_caustic_photons(scene, job_lights(job), settings, nullptr);
    EXPECT_EQ(progress.load(), 1'000);
    settings.progress = nullptr;
    EXPECT_EQ(unmapped.lights[0].candidates, 30'000);
    EXPECT_EQ(unmapped.lights[0].traced, 30'000);
    EXPECT_NEAR(stored_power(unmapped) / stored_power(given), 1.0, 0.02);

    // A raised count that could not fit is refused before anything is shot, naming the option
    // that raised it.
    settings.min_traced_per_light = 1e9;
    settings.memory_budget_bytes = 64.0 * (1 << 20);
    try {
        shoot_caustic_photons(scene, job_lights(job), settings, nullptr);
        FAIL() << "expected a refusal";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--photons-per-pixel raised --caustic-num-photons to 1000000000:", 0), 0u)
            << e.what();
    }
}

TEST(Photons, PhotonsPerPixelSetTheTracedCountOfAProgressivePass) {
    // --photons-per-pixel K: K photons per image pixel traced a pass, shared by the lights.
    JobBuilder b = virtual_light_scene(false);
    b.light({0.3, 1, 0}, {1, 1, 1}, {0, 0, 1});  // a second light: each traces half
    b.job.options.integrator = IntegratorKind::progressive;
    b.job.options.projection_map = ProjectionMapMode::on;
    b.job.options.caustic_num_photons = 100;
    b.job.options.photons_per_pixel = 3.0;
    const RenderJob job = b.build();
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, false));
    CausticStage stage;
    build_progressive_pass(stage, scene, job, nullptr, PhotonPassExtras{});
    ASSERT_EQ(stage.lights.size(), 2u);
    const double each = 3.0 * job.width * job.height / 2.0;  // 3 456
    for (const LightCausticStats& l : stage.lights) {
        EXPECT_TRUE(l.projection_map_used);
        EXPECT_GE(static_cast<double>(l.traced), each - 1.0);
        EXPECT_LE(static_cast<double>(l.traced), each + 2.0);
    }
    // The automatic choice tries a map whatever the count asked: the raised count is what it saves.
    JobBuilder automatic = b;
    automatic.job.options.projection_map = ProjectionMapMode::automatic;
    const RenderJob auto_job = automatic.build();
    CausticStage auto_stage;
    build_progressive_pass(auto_stage, scene, auto_job, nullptr, PhotonPassExtras{});
    ASSERT_EQ(auto_stage.lights.size(), 2u);
    for (const LightCausticStats& l : auto_stage.lights) {
        EXPECT_TRUE(l.projection_map_used);
        EXPECT_GE(static_cast<double>(l.traced), each - 1.0);
        EXPECT_LE(static_cast<double>(l.traced), each + 2.0);
    }
}
