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
