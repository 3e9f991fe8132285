// Numerical stability at the extremes: every case gives a correct image or a clear error, never a
// NaN pixel, a hang or a crash. Each test backs one row of docs/ACCURACY.md.
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/scene/source_location.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace caustica;
using caustica::testing::JobBuilder;
using caustica::testing::virtual_light_scene;

namespace {

/// Every pixel finite, and a lit image: at least a tenth of the pixels above 1/255 in some
/// channel (every scene here is lit where the camera looks; an all-black image is a failure too).
void expect_finite(const Image& image, const char* what) {
    std::size_t bad = 0, lit = 0;
    for (const glm::vec3& p : image.pixels) {
        bad += !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        lit += std::max({p.x, p.y, p.z}) > 1.0f / 255.0f;
    }
    EXPECT_EQ(bad, 0u) << what;
    EXPECT_GE(10 * lit, image.pixels.size()) << what << ": " << lit << " lit pixels of " << image.pixels.size();
}

double mean_red(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels) sum += p.x;
    return sum / static_cast<double>(image.pixels.size());
}

/// The mean red of the caustic alone: the caustics-only image less the same without photons
/// (the classic integrator's caustics-only view keeps its other light).
double caustic_part(JobBuilder b) {
    b.job.options.draw_caustics_only = true;
    const double with = mean_red(caustica::testing::render(b.build()));
    b.job.options.no_caustic_map = true;
    return with - mean_red(caustica::testing::render(b.build()));
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
    // A photon carries 4 pi d_u^2 / (c2 N) of the light's power (docs/CAUSTICS.md): with the
    // gather distance held fixed, the caustic (the caustics-only image less the same image
    // without photons, which keeps the classic view's other light) scales exactly as d_u^2, from
    // 1e-8 to 1e8 times. With the default gather distance (0.15 d_u) the image stays finite.
    auto caustic = [](double d) {
        JobBuilder b = virtual_light_scene(false);
        b.job.options.caustic_num_photons = 20'000;
        b.job.options.unit_distance = d;
        expect_finite(caustica::testing::render(b.build()), "unit distance");
        b.job.options.caustic_max_dist = 0.3;
        return caustic_part(b);
    };
    const double at_one = caustic(1.0);
    ASSERT_GT(at_one, 1e-3);  // a caustic to scale
    // Float pixels of about 0.3 resolve the caustic's mean to about 1e-8 (at d_u = 1e-2 it is 2e-6).
    for (double d : {1e-2, 0.5, 2.0, 1e2, 1e4})
        EXPECT_NEAR(caustic(d) / (at_one * d * d), 1.0, 1e-4 + 1e-8 / (at_one * d * d)) << "unit distance " << d;
    EXPECT_NEAR(caustic(1e-4), at_one * 1e-8, 1e-8);
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
    // The caustic under the ball is still there at index 4 (the ball focuses inside itself and the
    // light leaves it spread: a dimmer caustic per pixel is allowed, none is not).
    double caustic[2];
    int i = 0;
    for (double n : {1.5, 4.0}) {
        JobBuilder b = glass_ball(n);
        b.job.options.caustic_num_photons = 50'000;
        expect_finite(caustica::testing::render(b.build()), "index");
        caustic[i++] = caustic_part(b);
    }
    EXPECT_GT(caustic[0], 1e-3);
    EXPECT_GT(caustic[1], 0.05 * caustic[0]);
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
    b.job.options.caustic_num_photons = 10'000;
    b.scene->lights[0].radius = 0.0;  // a point light
    const Image point = caustica::testing::render(b.build());
    expect_finite(point, "point light");
    b.scene->lights[0].radius = 1e-30;  // a sphere of vanishing size: the point light's image
    const Image tiny = caustica::testing::render(b.build());
    expect_finite(tiny, "tiny light");
    EXPECT_NEAR(mean_red(tiny), mean_red(point), 1e-3 * mean_red(point));
    b.scene->lights[0].colour = {0, 0, 0};  // a black light adds nothing: the image without it
    const Image dark = caustica::testing::render(b.build());
    expect_finite(dark, "black light");
    b.job.lights.clear();
    const Image none = caustica::testing::render(b.build());
    ASSERT_EQ(dark.pixels.size(), none.pixels.size());
    for (std::size_t i = 0; i < dark.pixels.size(); ++i) ASSERT_EQ(dark.pixels[i], none.pixels[i]) << i;
}
