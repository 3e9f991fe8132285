// Progressive photon mapping (docs/CAUSTICS.md): the accumulation converges to analytic answers,
// keeps energy whatever the projection maps, the thread count or the scale, and is bit-identical
// for any thread count with --reproducible. Each test is sized to run in about a second in Release;
// under the sanitizers (CAUSTICA_SANITIZED) the longer ones do less (fewer passes, lights, scales).
#include "tests/scene_test_helpers.h"
#include "tests/test_support.h"

#include "core/scene/camera.h"
#include "core/util/sanitized.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

// ---- the virtual light ------------------------------------------------------------------------

/// The virtual-light scene's caustic on its ceiling (y = 2.95) is the direct light of a point
/// light of intensity ks = 0.9 at the mirror image (0, -1, 0) of the real one, with falloff
/// 1 / d^2: the pixel shows kd I cos(theta) / d^2, kd = 0.8 (the photon term is kd E).
double virtual_light_radiance(const glm::dvec3& p) {
    const glm::dvec3 d = p - glm::dvec3(0.0, -1.0, 0.0);
    const double d2 = glm::dot(d, d);
    return 0.8 * 0.9 * (d.y / std::sqrt(d2)) / d2;
}

/// The analytic image over a ring of the ceiling: the pixels whose four corners see the ceiling
/// between radii `inner` and `outer`, each with the mean of virtual_light_radiance over its
/// footprint (8 x 8 points), which is what jittered samples average to.
struct AnalyticRing {
    std::vector<std::size_t> pixels;
    std::vector<double> value;
};

AnalyticRing virtual_light_ring(const RenderJob& job, double inner, double outer) {
    const Camera camera(job.camera, job.width, job.height);
    auto ceiling = [&](double x, double y) {
        const Ray ray = camera.generate(static_cast<float>(x), static_cast<float>(y));
        const double t = (2.95 - ray.origin.y) / ray.direction.y;
        return glm::dvec3(ray.origin) + t * glm::dvec3(ray.direction);
    };
    AnalyticRing ring;
    constexpr int sub = 8;
    for (int y = 0; y < job.height; ++y)
        for (int x = 0; x < job.width; ++x) {
            bool inside = true;
            for (int c = 0; c < 4; ++c) {
                const glm::dvec3 p = ceiling(x + (c & 1), y + (c >> 1));
                const double r = std::hypot(p.x, p.z);
                inside = inside && r >= inner && r <= outer;
            }
            if (!inside) continue;
            double sum = 0.0;
            for (int j = 0; j < sub; ++j)
                for (int i = 0; i < sub; ++i) sum += virtual_light_radiance(ceiling(x + (i + 0.5) / sub, y + (j + 0.5) / sub));
            ring.pixels.push_back(static_cast<std::size_t>(y) * job.width + x);
            ring.value.push_back(sum / (sub * sub));
        }
    return ring;
}

struct RingError {
    double rmse = 0.0;  ///< relative: RMS of the pixel errors over the mean analytic value
    double mean = 0.0;  ///< relative error of the ring's mean
};

RingError ring_error(const Image& image, const AnalyticRing& ring) {
    double squared = 0.0, sum = 0.0, truth = 0.0;
    for (std::size_t k = 0; k < ring.pixels.size(); ++k) {
        const double d = image.pixels[ring.pixels[k]].x - ring.value[k];
        squared += d * d;
        sum += d;
        truth += ring.value[k];
    }
    const double n = static_cast<double>(ring.pixels.size());
    return {std::sqrt(squared / n) / (truth / n), sum / truth};
}

/// Least-squares slope of log(y) against log(x).
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    const double n = static_cast<double>(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// ---- means per pass ---------------------------------------------------------------------------

double image_mean(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& c : image.pixels) sum += (static_cast<double>(c.x) + c.y + c.z) / 3.0;
    return sum / static_cast<double>(image.pixels.size());
}

/// The image mean of an accumulation and its standard error, from the spread of the passes' own
/// image means: the job is rendered one pass at a time (resume), and pass p's image is recovered
/// from the running means as p m_p - (p - 1) m_{p-1}. Passes are independent (fresh photons,
/// fresh jitter), so the spread of their means measures the noise of the result.
struct MeanAndError {
    double mean = 0.0, sigma = 0.0;
    Image image;
};

MeanAndError accumulate_one_pass_at_a_time(const RenderJob& job, int passes) {
    RenderSession session;
    session.set_job(job);
    std::vector<double> means;
    double previous = 0.0;
    for (int p = 1; p <= passes; ++p) {
        // A target error no estimate reaches makes even a one-pass limit accumulate (passes = 1
        // alone is the single k-nearest pass, which cannot be resumed).
        session.set_stop_rules(p, 0.0, 1e-12);
        if (p == 1) session.start();
        else EXPECT_TRUE(session.resume());
        EXPECT_TRUE(session.wait());
        const double mean = image_mean(session.image());
        means.push_back(p * mean - (p - 1) * previous);
        previous = mean;
    }
    EXPECT_EQ(session.stats().accumulation.passes, passes);
    double sum = 0.0, squares = 0.0;
    for (double m : means) sum += m, squares += m * m;
    MeanAndError r;
    r.mean = sum / passes;
    r.sigma = std::sqrt(std::max(0.0, squares - sum * sum / passes) / (passes - 1) / passes);
    r.image = session.image();
    return r;
}

}  // namespace

// The virtual light converges to the analytic answer within 1% and the error keeps
// falling between pass 10 and pass 1000 with a log-log slope steeper than -0.25 (Knaus & Zwicker
// with alpha = 2/3: noise and bias both fall as n^(-1/3)).
//
// "Within 1%" is the relative RMSE over the ring's pixels (per-pixel convergence, which implies
// the ring's mean within 1% too; both are checked). The ring (radii 1 to 1.4 on the ceiling) is
// seen by the camera past the blocker (which hides radii below 0.86) and its first gathers
// (r_1 = 0.6: N = 1000 is more than the ~30 photons a pass leaves within 0.6, so r_1 is the
// maximum distance everywhere) stay clear of the blocker's shadow (radius <= 0.4) and of the
// ceiling's edge (2). A large r_1 keeps the noise low; the irradiance is smooth (relative bias of
// a disc of radius r about r^2 / 20), so the bias it brings is small and shrinks with r.
// Measured over six seeds: RMSE 0.53-0.61% at pass 1000, slope -0.30 to -0.36.
// One accumulation is continued with set_stop_rules + resume() to report the intermediate
// passes; the result equals a single run (ProgressiveStopping.ResumeContinuesTheAccumulation).
TEST(ProgressiveConvergence, VirtualLightConvergesToTheAnalyticAnswer) {
    JobBuilder b = caustica::testing::virtual_light_scene(false);
    b.job.width = b.job.height = 32;
    b.job.options.integrator = IntegratorKind::progressive;
    b.job.options.caustic_num_photons = 8'000;
    b.job.options.caustic_num_neighbours = 1000;
    b.job.options.caustic_max_dist = 0.6;
    b.job.options.draw_caustics_only = true;
    b.job.miss_colour = {0, 0, 0};
    const RenderJob job = b.build();
    const AnalyticRing ring = virtual_light_ring(job, 1.0, 1.4);
    ASSERT_GE(ring.pixels.size(), 40u);
    {  // the formula is the renderer's own direct light of the mirrored light at pixel centres
        JobBuilder mirrored = caustica::testing::virtual_light_scene(true);
        mirrored.job.width = mirrored.job.height = job.width;
        mirrored.job.options.integrator = IntegratorKind::progressive;
        const Image centres = caustica::testing::render(mirrored.build());
        const Camera camera(job.camera, job.width, job.height);
        for (std::size_t i : ring.pixels) {
            const Ray ray = camera.generate(static_cast<float>(i % job.width) + 0.5f,
                                            static_cast<float>(i / job.width) + 0.5f);
            const double t = (2.95 - ray.origin.y) / ray.direction.y;
            const double v = virtual_light_radiance(glm::dvec3(ray.origin) + t * glm::dvec3(ray.direction));
            ASSERT_NEAR(centres.pixels[i].x / v, 1.0, 1e-4) << "pixel " << i;
        }
    }
    // Under the sanitizers (5-10 times slower) the accumulation stops at pass 300, where the
    // RMSE measured 0.9-1.3%.
    const int last = sanitized_build ? 300 : 1000;
    const double final_bound = sanitized_build ? 0.02 : 0.01;
    std::vector<double> passes, rmse;
    RenderSession session;
    session.set_job(job);
    for (int n : {10, 15, 22, 33, 50, 75, 110, 165, 250, 370, 550, 800, 1000}) {
        if (n > last) break;
        session.set_stop_rules(n, 0.0, 0.0);
        if (passes.empty()) session.start();
        else ASSERT_TRUE(session.resume());
        ASSERT_TRUE(session.wait());
        ASSERT_EQ(session.stats().accumulation.passes, n);
        const RingError e = ring_error(session.image(), ring);
        passes.push_back(n);
        rmse.push_back(e.rmse);
        std::printf("pass %4d: relative RMSE %.4f, mean %+.4f, radius %.3f\n", n, e.rmse, e.mean,
                    session.stats().accumulation.radius);
    }
    const RingError final_error = ring_error(session.image(), ring);
    const double slope = log_log_slope(passes, rmse);
    std::printf("slope of log RMSE against log passes: %.3f\n", slope);
    EXPECT_LT(final_error.rmse, final_bound);
    EXPECT_LT(std::abs(final_error.mean), final_bound);
    EXPECT_LT(slope, -0.25);
    EXPECT_LT(rmse.back(), 0.5 * rmse.front());
}

// Inside a closed diffuse sphere of radius R and albedo rho, with a point light
// anywhere inside, the indirect irradiance is the same everywhere: rho / (1 - rho) times the mean
// direct irradiance Phi / (4 pi R^2). With Phi = 4 pi C d_u^2 / c2 (the photon energy rule, d_u =
// c2 = 1) that is rho / (1 - rho) C / R^2 and the pixel shows kd E with kd = rho. Without --gi
// it is 0.
//
// The light's colour C puts E at 0.15, so that no pass's estimate nears the clamp at 1 whatever
// rho. r_1 is the maximum distance 0.3 everywhere (N above the photons within it) so that each
// gather averages many photons. The camera (150 degrees, at the centre) sees about 40% of the
// wall; the image mean's standard error comes from the spread of its 8 passes. Measured over six
// seeds and the light positions: 0.2-0.45% (rho 0.2), 0.2-0.45% (0.5), 0.2-0.3% (0.9) with the
// photon counts below (a path stores rho / (1 - rho) photons: 1 in 4 for rho 0.2, 9 for rho 0.9),
// so 2% is >= 4 sigma; the deviations measured were all within 0.7% (all slightly low, by 0.3%
// on average). The guard below keeps that margin honest.
class ProgressiveGiSphere : public ::testing::TestWithParam<double> {};

TEST_P(ProgressiveGiSphere, IndirectIrradianceIsUniformAndAnalytic) {
    const double rho = GetParam(), radius = 2.0, irradiance = 0.15;
    const long long photons = rho < 0.3 ? 200'000 : rho < 0.7 ? 90'000 : 15'000;
    const double colour = irradiance * (1.0 - rho) * radius * radius / rho;
    // Off centre, and 0.09 and 0.035 from the wall (the last in front of the camera). Under the
    // sanitizers, only the first.
    const std::vector<glm::dvec3> lights = {glm::dvec3(-1.2, 0.4, 0.6), glm::dvec3(0.2, -1.88, 0.3), glm::dvec3(1.9, 0.3, 0.4)};
    for (std::size_t l = 0; l < (sanitized_build ? 1 : lights.size()); ++l) {
        const glm::dvec3 light = lights[l];
        ASSERT_LT(glm::length(light), radius);
        for (bool gi : {true, false}) {
            JobBuilder b(16, 16);
            const int ball = b.add(NodeKind::sphere, b.material(glm::dvec3(rho)));
            b.scale(ball, glm::dvec3(radius));
            b.light(light, glm::dvec3(colour), {0, 0, 1});
            b.camera({0, 0, 0}, {1, 0, 0}, 150);
            b.job.options.integrator = IntegratorKind::progressive;
            b.job.options.gi = gi;
            b.job.options.gi_num_photons = photons;
            b.job.options.caustic_num_photons = photons;
            b.job.options.caustic_max_dist = 0.3;
            b.job.options.caustic_num_neighbours = 2000;
            b.job.options.draw_caustics_only = true;
            const RenderJob job = b.build();
            if (!gi) {  // nothing specular: no photons at all, and no photon term
                const Image image = caustica::testing::render(job);
                EXPECT_EQ(image_mean(image), 0.0) << "rho " << rho;
                continue;
            }
            const MeanAndError m = accumulate_one_pass_at_a_time(job, 8);
            const double expected = rho * irradiance;
            std::printf("rho %.1f, light (%.2f, %.2f, %.2f): mean / analytic %.4f, standard error %.4f\n", rho, light.x,
                        light.y, light.z, m.mean / expected, m.sigma / expected);
            EXPECT_NEAR(m.mean / expected, 1.0, 0.02) << "rho " << rho << ", light " << light.x << " " << light.y;
            EXPECT_LT(m.sigma / expected, 0.0075) << "too noisy for a 2% bound";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Albedos, ProgressiveGiSphere, ::testing::Values(0.2, 0.5, 0.9));

namespace {

/// A closed diffuse box (the unit cube, kd 0.6) with a mirror slab over most of its floor and a
/// glass ball above it, lit by a point light in the middle; the camera looks at the ceiling and
/// the walls, where the mirror and the ball send their caustics (reflected, and refracted then
/// reflected), and the ball's shadow in them. Scene, light, camera and unit distance scale together.
JobBuilder closed_caustic_box(double scale) {
    JobBuilder b(32, 32);
    const int root = b.add(NodeKind::group, -1);
    b.scale(root, glm::dvec3(scale));
    b.add(NodeKind::cube, b.material({0.6, 0.6, 0.6}), root);
    const int mirror = b.add(NodeKind::cube, b.material({0, 0, 0}, glm::dvec3(0.9), 0, true), root);
    b.translate(mirror, {0.0, -0.95, 0.0});
    b.scale(mirror, {0.95, 0.02, 0.95});
    MaterialDesc glass;
    glass.ks = glm::dvec3(0.9);
    glass.refractive_index = 1.5;
    b.scene->materials.push_back(glass);
    const int ball = b.add(NodeKind::sphere, static_cast<int>(b.scene->materials.size()) - 1, root);
    b.translate(ball, {0.4, -0.5, -0.3});
    b.scale(ball, glm::dvec3(0.3));
    b.light(glm::dvec3(0.0), {1, 1, 1}, {0, 0, 1});
    b.camera(glm::dvec3(0.0, -0.5, 0.9) * scale, {0, 1, -0.4}, 110);
    b.job.options.integrator = IntegratorKind::progressive;
    b.job.options.unit_distance = scale;
    b.job.options.draw_caustics_only = true;
    b.job.options.caustic_num_photons = 100'000;
    b.job.options.caustic_num_neighbours = 50;
    b.job.options.caustic_max_dist = 0.15 * scale;
    return b;
}

}  // namespace

// A closed scene renders the same mean with the projection maps on and off, at any
// scale (scene and unit distance scaled together). The mean of 8 passes has a standard error of
// 0.3-0.5% (measured over seven seeds, and printed): 2.5% is > 4 sigma of the difference of two
// independent means (the same seed is used, so that in practice the difference is smaller still:
// the maps only skip directions that reach nothing specular). The thread count is the next test.
// Under the sanitizers, scales 1 and 1000 only. Guided emission is off: it moves photons away from
// the box's focus, which is far above white and holds most of the mean, so that the mean itself
// gets noisier by design (0.87% against 0.5%); GuidedEmission.KeepsTheCausticEnergyOfPlainEmission
// checks its energy.
TEST(ProgressiveConvergence, ClosedSceneKeepsItsEnergyWithAndWithoutProjectionMapsAtAnyScale) {
    double reference = 0.0;
    const std::vector<double> scales = sanitized_build ? std::vector<double>{1.0, 1e3} : std::vector<double>{1.0, 1e-3, 1e3};
    for (double scale : scales) {
        for (ProjectionMapMode mode : {ProjectionMapMode::on, ProjectionMapMode::off}) {
            JobBuilder b = closed_caustic_box(scale);
            b.job.options.projection_map = mode;
            b.job.options.guided_emission = false;
            const MeanAndError m = accumulate_one_pass_at_a_time(b.build(), 8);
            std::printf("scale %g, projection maps %s: mean %.6f, standard error %.2f%%\n", scale,
                        mode == ProjectionMapMode::on ? "on" : "off", m.mean, 100.0 * m.sigma / m.mean);
            EXPECT_LT(m.sigma, 0.0075 * m.mean) << "too noisy for a 2.5% bound";
            ASSERT_GT(m.mean, 0.0);
            if (reference == 0.0) reference = m.mean;
            EXPECT_NEAR(m.mean / reference, 1.0, 0.025) << "scale " << scale << (mode == ProjectionMapMode::on ? " on" : " off");
        }
    }
}

// The passes are deterministic per (pixel, pass), so --reproducible renders the same
// bits for any thread count: caustic photons (with projection maps) and --gi.
TEST(ProgressiveConvergence, ReproducibleAccumulationIsBitIdenticalForAnyThreadCount) {
    for (bool gi : {false, true}) {
        std::vector<Image> images;
        for (int threads : {1, 2}) {
            JobBuilder b = closed_caustic_box(1.0);
            b.job.width = b.job.height = 24;
            b.job.options.caustic_num_photons = 20'000;
            b.job.options.gi = gi;
            b.job.options.gi_num_photons = 20'000;
            b.job.options.passes = 4;
            b.job.options.threads = threads;
            RenderSession session;
            session.set_job(b.build());
            session.start();
            ASSERT_TRUE(session.wait());
            ASSERT_EQ(session.stats().accumulation.passes, 4);
            images.push_back(session.image());
        }
        ASSERT_GT(image_mean(images[0]), 0.0);
        for (std::size_t t = 1; t < images.size(); ++t) {
            std::size_t differing = 0;
            for (std::size_t i = 0; i < images[0].pixels.size(); ++i)
                differing += images[t].pixels[i] != images[0].pixels[i] ? 1 : 0;
            EXPECT_EQ(differing, 0u) << (gi ? "--gi, " : "caustics, ") << t + 1 << " threads against 1";
        }
    }
}

// ---- the roulette of faint paths ------------------------------------------------------------

namespace {

/// A glass ball (index 1.5, ks 1) before a uniform grey sky, with no light and no ambient: every
/// path ends in the sky, and at each surface the reflected and the refracted branches carry R and
/// 1 - R, so every pixel shows the sky's 0.5 whatever the path tree (the ball is invisible). No
/// weight cut, and depth 32: only rays grazing the silhouette, reflected inside with R near 1,
/// lose anything.
RenderJob invisible_ball(double roulette_weight) {
    RenderJob job = caustica::testing::load_first_job(R"(
glass = gr.material({0, 0, 0}, {1, 1, 1}, 0)
glass:set_ri(1.5)
ball = gr.sphere('ball')
ball:set_material(glass)
root = gr.node('root')
root:add_child(ball)
gr.set_miss_colour({0.5, 0.5, 0.5})
gr.render(root, 'ball.png', 24, 24, {0, 0, 4}, {0, 0, -1}, {0, 1, 0}, 40, {0, 0, 0}, {})
)");
    job.options.integrator = IntegratorKind::progressive;
    job.options.min_weight = 0.0;
    job.options.max_depth = 32;
    job.options.roulette_weight = roulette_weight;
    return job;
}

}  // namespace

// Without the roulette every branch is traced and the pixels are 0.5 to rounding. With it at 1
// (every branch goes on at random, with probability its weight) a pass is noisy but its mean is
// still 0.5: over 64 passes the image mean is within 4 standard errors (from the spread of the
// passes' means) of 0.5, with far fewer rays. A roulette whose survivors did not carry their
// weight divided by their chance would read far below 0.5 (the entry alone costs R or 1 - R).
TEST(ProgressiveRoulette, FaintBranchesTracedAtRandomKeepTheImageOnAverage) {
    RenderJob full = invisible_ball(0.0);
    full.options.passes = 4;
    RenderSession session;
    session.set_job(full);
    session.start();
    ASSERT_TRUE(session.wait());
    const Image exact = session.image();
    const std::uint64_t full_rays = session.stats().rays.reflected + session.stats().rays.refracted;
    // Only a pixel whose jittered sample grazes the silhouette may lose anything (two measured).
    int exact_pixels = 0;
    for (const glm::vec3& c : exact.pixels) {
        ASSERT_NEAR(c.x, 0.5f, 1e-3f);
        exact_pixels += std::fabs(c.x - 0.5f) <= 1e-5f;
    }
    EXPECT_GE(exact_pixels, static_cast<int>(exact.pixels.size()) - 4);
    EXPECT_NEAR(image_mean(exact), 0.5, 1e-5);

    const int passes = sanitized_build ? 16 : 64;
    const MeanAndError at_random = accumulate_one_pass_at_a_time(invisible_ball(1.0), passes);
    std::printf("roulette 1: mean %.5f +- %.5f over %d passes\n", at_random.mean, at_random.sigma, passes);
    EXPECT_GT(at_random.sigma, 1e-4);  // the roulette did make the passes differ
    EXPECT_NEAR(at_random.mean, 0.5, 4.0 * at_random.sigma);
    EXPECT_NEAR(image_mean(at_random.image), 0.5, 4.0 * at_random.sigma);
    // Fewer rays: a pass with the roulette at 1 traces one branch per surface on average.
    RenderJob one = invisible_ball(1.0);
    one.options.passes = 4;
    session.set_job(one);
    session.start();
    ASSERT_TRUE(session.wait());
    const std::uint64_t random_rays = session.stats().rays.reflected + session.stats().rays.refracted;
    std::printf("secondary rays in 4 passes: %llu traced in full, %llu at random\n",
                static_cast<unsigned long long>(full_rays), static_cast<unsigned long long>(random_rays));
    EXPECT_LT(random_rays, full_rays * 3 / 4);
}
