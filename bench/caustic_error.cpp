// Error per photon of the caustic estimate: low-discrepancy against random emission, the original's
// disc average against Jensen's cone filter, on the virtual-light scene whose answer is known
// (the ceiling lit through a mirror equals a light of intensity ks I at the mirrored position).
// Prints a Markdown table.   build/caustic_error [--quick]
#include "core/render/render_session.h"
#include "tests/test_support.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

using namespace caustica;
using caustica::testing::virtual_light_scene;

namespace {

struct Run {
    double rmse, relative_bias, photon_seconds, render_seconds;
};

Run measure(long long photons, bool random_emission, bool cone, int neighbours, const Image& truth,
            const std::vector<std::size_t>& pixels) {
    caustica::testing::JobBuilder b = virtual_light_scene(false);
    b.job.width = b.job.height = 96;
    b.job.options.caustic_num_photons = photons;
    b.job.options.caustic_num_neighbours = neighbours;
    b.job.options.photon_random_emission = random_emission;
    b.job.options.caustic_cone_filter = cone;
    b.job.options.draw_caustics_only = true;
    b.job.options.integrator = IntegratorKind::progressive;  // the physics the virtual light's answer follows
    RenderSession session;
    session.set_job(b.build());
    session.start();
    session.wait();
    const RenderStats stats = session.stats();
    double photon_seconds = 0.0, render_seconds = 0.0;
    for (const StageTime& s : stats.stages) {
        if (s.name == "projection maps" || s.name == "photon shooting" || s.name == "photon k-d tree")
            photon_seconds += s.seconds;
        if (s.name == "first samples") render_seconds += s.seconds;
    }
    double squared = 0.0, sum = 0.0, sum_truth = 0.0;
    for (std::size_t i : pixels) {
        const double d = session.image().pixels[i].x - truth.pixels[i].x;
        squared += d * d;
        sum += session.image().pixels[i].x;
        sum_truth += truth.pixels[i].x;
    }
    const double mean_truth = sum_truth / static_cast<double>(pixels.size());
    return {std::sqrt(squared / static_cast<double>(pixels.size())) / mean_truth, sum / sum_truth - 1.0,
            photon_seconds, render_seconds};
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc == 2 && std::strcmp(argv[1], "--quick") == 0;
    if (argc > 2 || (argc == 2 && !quick)) {  // --help, or anything it does not know
        const bool help = std::strcmp(argv[1], "--help") == 0;
        std::fprintf(help ? stdout : stderr,
                     "usage: caustic_error [--quick]   (a Markdown table of the caustic estimate's error per photon "
                     "on the virtual light; docs/ACCURACY.md)\n");
        return help ? 0 : 2;
    }
    caustica::testing::JobBuilder reference = virtual_light_scene(true);
    reference.job.width = reference.job.height = 96;
    reference.job.options.integrator = IntegratorKind::progressive;
    const RenderJob reference_job = reference.build();
    const Image truth = caustica::testing::render(reference_job);
    const std::vector<std::size_t> pixels = caustica::testing::virtual_light_annulus(reference_job);

    std::printf("| photons | N | emission | filter | relative RMSE | mean bias | photon s | render s |\n");
    std::printf("|---:|---:|---|---|---:|---:|---:|---:|\n");
    const std::vector<long long> counts = quick ? std::vector<long long>{10'000, 100'000}
                                                : std::vector<long long>{10'000, 30'000, 100'000, 300'000, 1'000'000, 3'000'000};
    for (long long photons : counts)
        for (int neighbours : {50, 200})
            for (bool random_emission : {false, true})
                for (bool cone : {false, true}) {
                    const Run r = measure(photons, random_emission, cone, neighbours, truth, pixels);
                    std::printf("| %lld | %d | %s | %s | %.4f | %+.4f | %.3f | %.3f |\n", photons, neighbours,
                                random_emission ? "random" : "low-discrepancy", cone ? "cone" : "disc", r.rmse,
                                r.relative_bias, r.photon_seconds, r.render_seconds);
                }
    return 0;
}
