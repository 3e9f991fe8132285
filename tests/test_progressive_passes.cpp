// Progressive photon mapping (issue 11, in progress): passes of fresh photons gathered with a
// shrinking radius converge to the analytic caustic of the virtual-light scene.
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

/// Relative RMSE of `image` against `reference` over the virtual-light annulus (red channel).
double annulus_error(const Image& image, const Image& reference, const RenderJob& job) {
    double squared = 0.0, sum = 0.0;
    const std::vector<std::size_t> pixels = caustica::testing::virtual_light_annulus(job);
    for (std::size_t i : pixels) {
        const double d = image.pixels[i].x - reference.pixels[i].x;
        squared += d * d;
        sum += reference.pixels[i].x;
    }
    const double n = static_cast<double>(pixels.size());
    return std::sqrt(squared / n) / (sum / n);
}

}  // namespace

TEST(ProgressivePasses, VirtualLightErrorFallsWithPasses) {
    JobBuilder reference = caustica::testing::virtual_light_scene(true);
    reference.job.options.integrator = IntegratorKind::progressive;
    reference.job.miss_colour = {0, 0, 0};
    const Image truth = caustica::testing::render(reference.build());
    double errors[3];
    int i = 0;
    for (int passes : {1, 8, 64}) {
        JobBuilder b = caustica::testing::virtual_light_scene(false);
        b.job.options.integrator = IntegratorKind::progressive;
        b.job.options.caustic_num_photons = 20'000;
        b.job.options.caustic_max_dist = 0.3;
        b.job.options.passes = passes;
        b.job.options.draw_caustics_only = true;
        b.job.miss_colour = {0, 0, 0};
        const RenderJob job = b.build();
        errors[i++] = annulus_error(caustica::testing::render(job), truth, job);
    }
    std::printf("relative RMSE after 1, 8, 64 passes: %.4f %.4f %.4f\n", errors[0], errors[1], errors[2]);
    EXPECT_LT(errors[1], errors[0]);
    EXPECT_LT(errors[2], 0.6 * errors[1]);
}

// Inside a closed diffuse sphere of radius R and albedo rho, with a point light anywhere inside,
// the indirect irradiance is the same everywhere: rho / (1 - rho) times the mean direct
// irradiance Phi / (4 pi R^2). With Phi = 4 pi C d_u^2 / c2 (the photon energy rule), the
// photon term of a pixel is kd E = rho^2 / (1 - rho) C d_u^2 / (c2 R^2). Without --gi it is 0.
TEST(ProgressiveGi, ClosedDiffuseSphereMatchesTheAnalyticInterreflection) {
    for (const auto& [rho, light] : {std::pair{0.5, glm::dvec3(0.5, 0.3, -0.2)}, std::pair{0.8, glm::dvec3(-1.2, 0.4, 0.6)}}) {
        for (bool gi : {true, false}) {
            JobBuilder b(16, 16);
            const double radius = 2.0;
            const int ball = b.add(NodeKind::sphere, b.material(glm::dvec3(rho)));
            b.scale(ball, glm::dvec3(radius));
            b.light(light, {1, 1, 1}, {0, 0, 1});
            b.camera({0, 0, 0}, {1, 0, 0}, 40);
            b.job.options.integrator = IntegratorKind::progressive;
            b.job.options.gi = gi;
            b.job.options.gi_num_photons = 200'000;
            b.job.options.caustic_num_photons = 200'000;
            b.job.options.passes = 8;
            b.job.options.draw_caustics_only = true;
            const Image image = caustica::testing::render(b.build());
            double mean = 0.0;
            for (const glm::vec3& c : image.pixels) mean += c.x;
            mean /= static_cast<double>(image.pixels.size());
            const double expected = rho * rho / (1.0 - rho) / (radius * radius);
            std::printf("rho %.1f gi %d: mean %.5f, analytic %.5f\n", rho, gi ? 1 : 0, mean, gi ? expected : 0.0);
            if (gi) EXPECT_NEAR(mean / expected, 1.0, 0.02) << rho;
            else EXPECT_EQ(mean, 0.0) << rho;
        }
    }
}

// The renderer's own estimate of its remaining error stays within a factor 2 of the true error.
TEST(ProgressivePasses, ErrorEstimateTracksTheTrueErrorOnTheVirtualLight) {
    JobBuilder reference = caustica::testing::virtual_light_scene(true);
    reference.job.width = reference.job.height = 96;
    reference.job.options.integrator = IntegratorKind::progressive;
    reference.job.miss_colour = {0, 0, 0};
    const RenderJob truth_job = reference.build();
    const Image truth = caustica::testing::render(truth_job);
    for (int passes : {4, 16, 64}) {
        JobBuilder b = caustica::testing::virtual_light_scene(false);
        b.job.width = b.job.height = 96;
        b.job.options.integrator = IntegratorKind::progressive;
        b.job.options.caustic_num_photons = 20'000;
        b.job.options.caustic_num_neighbours = 20;
        b.job.options.caustic_max_dist = 0.3;
        b.job.options.passes = passes;
        b.job.options.draw_caustics_only = true;
        b.job.options.reproducible = true;
        b.job.miss_colour = {0, 0, 0};
        const RenderJob job = b.build();
        RenderSession session;
        session.set_job(job);
        session.start();
        ASSERT_TRUE(session.wait());
        const double truth_error = annulus_error(session.image(), truth, truth_job);
        const RenderStats::Accumulation a = session.stats().accumulation;
        std::printf("%d passes: true %.4f, estimated %.4f (noise %.4f, bias %.4f), radius %.4f -> %.4f\n", passes,
                    truth_error, a.error, a.noise, a.bias, a.first_radius, a.radius);
        EXPECT_GT(a.error, 0.5 * truth_error);
        EXPECT_LT(a.error, 2.0 * truth_error);
    }
}
