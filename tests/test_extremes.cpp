// Numerical stability at the extremes: every case gives a correct image or a clear error, never a
// NaN pixel, a hang or a crash. Each test backs one row of docs/ACCURACY.md.
#include "core/photons/caustic_stage.h"
#include "core/scene/source_location.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace caustica;
using caustica::testing::JobBuilder;
using caustica::testing::virtual_light_scene;

namespace {

void expect_finite(const Image& image, const char* what) {
    std::size_t bad = 0;
    for (const glm::vec3& p : image.pixels) bad += !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    EXPECT_EQ(bad, 0u) << what;
}

double mean_red(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels) sum += p.x;
    return sum / static_cast<double>(image.pixels.size());
}

/// A glass ball of index n on a floor, lit by a spherical light, with caustics.
JobBuilder glass_ball(double n) {
    JobBuilder b(40, 30);
    const int floor = b.add(NodeKind::cube, b.material({0.7, 0.7, 0.7}));
    b.translate(floor, {0, -1.1, 0});
    b.scale(floor, {4, 0.1, 4});
    MaterialDesc glass;
    glass.ks = {1, 1, 1};
    glass.refractive_index = n;
    b.scene->materials.push_back(glass);
    b.add(NodeKind::sphere, static_cast<int>(b.scene->materials.size()) - 1);
    b.light({0.5, 3, 1}, {2, 2, 2}, {0, 0, 1});
    b.camera({0, 0.5, 4}, {0, -0.15, -1}, 50);
    b.job.ambient = {0.1, 0.1, 0.1};
    return b;
}

}  // namespace

TEST(Extremes, UnitDistanceFrom1eMinus4To1e4) {
    for (double d : {1e-4, 1e-2, 1.0, 1e2, 1e4}) {
        JobBuilder b = virtual_light_scene(false);
        b.job.options.caustic_num_photons = 20'000;
        b.job.options.unit_distance = d;
        const Image image = caustica::testing::render(b.build());
        expect_finite(image, "unit distance");
    }
}

TEST(Extremes, SceneScaleFrom1eMinus4To1e5) {
    // Caustics only, unit distance scaled with the scene: the image must not change.
    double reference = -1.0;
    for (double s : {1e-4, 1e-2, 1.0, 1e3, 1e5}) {
        JobBuilder b = virtual_light_scene(false, s);
        b.job.options.caustic_num_photons = 100'000;
        b.job.options.draw_caustics_only = true;
        const Image image = caustica::testing::render(b.build());
        expect_finite(image, "scale");
        const double mean = mean_red(image);
        if (reference < 0.0) reference = mean;
        EXPECT_NEAR(mean / reference, 1.0, 0.01) << "scale " << s;
    }
}

TEST(Extremes, RefractiveIndex1And1Point0001And4) {
    const double plain = mean_red(caustica::testing::render(glass_ball(1.0).build()));
    const double almost = mean_red(caustica::testing::render(glass_ball(1.0001).build()));
    EXPECT_NEAR(almost, plain, 0.002 * plain + 1e-6);  // n = 1.0001 differs from n = 1 by a hair
    for (double n : {1.0, 1.0001, 4.0}) {
        JobBuilder b = glass_ball(n);
        b.job.options.caustic_num_photons = 50'000;
        expect_finite(caustica::testing::render(b.build()), "index");
    }
}

TEST(Extremes, GrazingIncidenceAndTotalInternalReflection) {
    // Camera exactly in the plane of a glass slab's top face: every ray grazes it; and a camera
    // inside a glass block looking up at its top at 60 degrees: total internal reflection.
    JobBuilder b(32, 32);
    MaterialDesc glass;
    glass.ks = {1, 1, 1};
    glass.refractive_index = 1.5;
    b.scene->materials.push_back(glass);
    const int slab = b.add(NodeKind::cube, 0);
    b.scale(slab, {3, 1, 3});
    const int back = b.add(NodeKind::cube, b.material({0.5, 0.6, 0.7}));
    b.translate(back, {0, 0, -10});
    b.scale(back, {20, 20, 0.1});
    b.light({0, 5, 5}, {1, 1, 1});
    b.camera({0, 1, 8}, {0, 0, -1}, 30);  // eye at y = 1: the top face's plane
    expect_finite(caustica::testing::render(b.build()), "grazing");
    b.camera({0, 0, 0}, {0, 1, -0.58}, 20);  // inside the glass, 60 degrees from the top's normal
    const Image inside = caustica::testing::render(b.build());
    expect_finite(inside, "total internal reflection");
}

TEST(Extremes, PhotonCountsFromZeroTo1e8AndBeyond) {
    JobBuilder b = glass_ball(1.5);
    b.job.options.caustic_num_photons = 0;
    EXPECT_FALSE(caustics_needed(b.build()));
    expect_finite(caustica::testing::render(b.build()), "0 photons");
    b.job.options.caustic_num_photons = 1;
    expect_finite(caustica::testing::render(b.build()), "1 photon");
    b.job.options.caustic_num_photons = 100'000'000;  // handled: only the map's ~1% are traced
    RenderSession session;
    session.set_job(b.build());
    session.start();
    ASSERT_TRUE(session.wait());
    expect_finite(session.image(), "1e8 photons");
    EXPECT_GT(session.stats().caustic_photons, 100'000u);
    b.job.options.caustic_num_photons = 100'000'000'000LL;  // refused before allocation
    session.set_job(b.build());
    session.start();
    EXPECT_THROW(session.wait(), InputError);
}

TEST(Extremes, NeighboursFromOneToMoreThanStored) {
    for (int n : {1, 2, 1000, 1'000'000}) {
        JobBuilder b = glass_ball(1.5);
        b.job.options.caustic_num_photons = 5'000;
        b.job.options.caustic_num_neighbours = n;
        b.job.options.caustic_max_dist = 10.0;
        expect_finite(caustica::testing::render(b.build()), "neighbours");
    }
}

TEST(Extremes, DegenerateTriangles) {
    // A mesh whose triangles have zero or vanishing area next to a proper one.
    JobBuilder b(24, 24);
    auto mesh = std::make_shared<MeshData>();
    mesh->path = "degenerate";
    mesh->positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {2, 2, 0}, {3, 3, 0}, {4, 4, 0},
                       {0, 0, 0.5f}, {1e-30f, 0, 0.5f}, {0, 1e-30f, 0.5f}};
    mesh->triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {0, 0, 1}};
    b.scene->meshes.push_back(mesh);
    const int node = b.add(NodeKind::mesh, b.material({0.6, 0.6, 0.6}, {0.3, 0.3, 0.3}, 10, true));
    b.scene->nodes[node].mesh = 0;
    b.light({0, 0, 5}, {1, 1, 1});
    b.camera({0, 0, 4}, {0, 0, -1}, 60);
    const Image image = caustica::testing::render(b.build());
    expect_finite(image, "degenerate triangles");
    EXPECT_GT(image.at(12, 12).x, 0.1f);  // the proper triangle is there
}

TEST(Extremes, ZeroAreaAndDarkLights) {
    JobBuilder b = glass_ball(1.5);
    b.scene->lights[0].radius = 0.0;  // a point light
    expect_finite(caustica::testing::render(b.build()), "point light");
    b.scene->lights[0].radius = 1e-30;  // a sphere of vanishing size
    b.job.options.caustic_num_photons = 10'000;
    expect_finite(caustica::testing::render(b.build()), "tiny light");
    b.scene->lights[0].colour = {0, 0, 0};
    expect_finite(caustica::testing::render(b.build()), "black light");
}
