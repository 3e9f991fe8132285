// Rendering one frame on several ranks (docs/SCALING.md), with threads standing in for the ranks
// (make_local_cluster: the protocol the MPI ranks follow, in one process, so that it runs under
// the sanitizers too; built into session_tests, which CI also runs under ThreadSanitizer). The image of K ranks is one process's, bit for bit, for both integrators;
// a failure or an interruption on one rank stops every rank with that rank's message. The same
// with real processes under mpirun: tests/app/test_mpi.cpp.
#include "tests/accumulation_orders.h"
#include "tests/test_support.h"

#include "core/photons/classic_photons.h"
#include "core/render/cluster.h"
#include "core/render/render_session.h"
#include "core/scene/source_location.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <chrono>
#include <cstring>
#include <limits>
#include <functional>
#include <string>
#include <thread>

using namespace caustica;

namespace {

/// A glass ball and a mirror post on a floor before a wall, one light with quadratic falloff
/// (caustic photons through the glass and off the mirror), built in C++: these tests also run
/// under ThreadSanitizer, without the script loader.
RenderJob caustic_box(IntegratorKind integrator) {
    caustica::testing::JobBuilder b(64, 48);
    const int white = b.material({0.7, 0.7, 0.7});
    const int blue = b.material({0.25, 0.35, 0.7});
    const int glass = b.material({0, 0, 0}, glm::dvec3(0.9), 60);
    b.scene->materials[static_cast<std::size_t>(glass)].refractive_index = 1.5;
    const int mirror = b.material({0, 0, 0}, glm::dvec3(0.85), 60, true);
    const int floor = b.add(NodeKind::cube, white);
    b.translate(floor, {-3, -1.1, -3});
    b.scale(floor, {6, 0.05, 6});
    const int wall = b.add(NodeKind::cube, blue);
    b.translate(wall, {-3, -1.1, -2.5});
    b.scale(wall, {6, 3.2, 0.05});
    const int ball = b.add(NodeKind::sphere, glass);
    b.translate(ball, {-0.6, -0.45, 0});
    b.scale(ball, glm::dvec3(0.55));
    const int post = b.add(NodeKind::cylinder, mirror);
    b.translate(post, {0.8, -0.6, -0.4});
    b.scale(post, {0.3, 0.4, 0.3});
    b.light({0.3, 2.2, 0.8}, {4.0, 4.0, 3.8}, {0.3, 0.0, 0.45});
    b.camera({0, 1.6, 4.6}, {0, -0.4, -1}, 45);
    b.job.ambient = {0.2, 0.2, 0.2};
    RenderJob job = b.build();
    job.options.integrator = integrator;
    job.options.resolution_override = 40;
    job.options.caustic_num_photons = 20'000;
    job.options.reproducible = true;
    job.options.silent = true;
    job.options.threads = 2;
    if (integrator == IntegratorKind::progressive) job.options.passes = 5;
    return job;
}

struct RankOutcome {
    Image image;
    RenderStats stats;
    bool completed = false;
    std::optional<RankFailure> failure;  ///< the ClusterError wait() threw
    std::string other_error;
};

/// Renders `jobs[k]` on rank k of a local cluster of jobs.size() ranks, one thread each; `before`
/// runs on each rank's session once it started (to cancel one).
std::vector<RankOutcome> render_on_ranks(std::vector<RenderJob> jobs,
                                         const std::function<void(int, RenderSession&)>& before = {}) {
    const int ranks = static_cast<int>(jobs.size());
    std::vector<std::unique_ptr<Cluster>> cluster = make_local_cluster(ranks);
    std::vector<RankOutcome> out(static_cast<std::size_t>(ranks));
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
        threads.emplace_back([&, r] {
            RankOutcome& o = out[static_cast<std::size_t>(r)];
            RenderSession session;
            session.set_cluster(cluster[static_cast<std::size_t>(r)].get());
            jobs[static_cast<std::size_t>(r)].options.threads = 1;
            session.set_job(jobs[static_cast<std::size_t>(r)]);
            session.start();
            if (before) before(r, session);
            try {
                o.completed = session.wait();
            } catch (const ClusterError& e) {
                o.failure = e.failure();
            } catch (const std::exception& e) {
                o.other_error = e.what();
            }
            o.image = session.image();
            o.stats = session.stats();
        });
    for (std::thread& t : threads) t.join();
    return out;
}

Image render_alone(const RenderJob& job, RenderStats* stats = nullptr) {
    RenderSession session;
    session.set_job(job);
    session.start();
    EXPECT_TRUE(session.wait());
    if (stats) *stats = session.stats();
    return session.image();
}

/// How many pixels differ in any bit.
int differing_pixels(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return -1;
    int n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        n += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(glm::vec3)) != 0;
    return n;
}

double mean_value(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& c : image.pixels) sum += c.x + c.y + c.z;
    return sum / (3.0 * static_cast<double>(image.pixels.size()));
}

/// Renders the accumulation `job` on 2 and 3 ranks: each makes `alone`, the image one process
/// made with `alone_stats`, bit for bit, with its passes, samples and estimate.
void expect_two_and_three_ranks_make(const RenderJob& job, const Image& alone, const RenderStats& alone_stats) {
    for (int ranks : {2, 3}) {
        const auto out = render_on_ranks(std::vector<RenderJob>(static_cast<std::size_t>(ranks), job));
        ASSERT_TRUE(std::all_of(out.begin(), out.end(), [](const RankOutcome& o) { return o.completed && !o.failure; }))
            << ranks << " ranks";
        EXPECT_EQ(differing_pixels(out[0].image, alone), 0) << ranks << " ranks";
        EXPECT_EQ(out[0].stats.accumulation.passes, job.options.passes);
        EXPECT_EQ(out[0].stats.rays.samples, alone_stats.rays.samples);
        EXPECT_EQ(out[0].stats.accumulation.error, alone_stats.accumulation.error);
    }
}

}  // namespace

TEST(Cluster, ProgressiveImageOnTwoAndThreeRanksIsOneProcesssBitForBit) {
    const RenderJob job = caustic_box(IntegratorKind::progressive);
    RenderStats alone_stats;
    const Image alone = render_alone(job, &alone_stats);
    ASSERT_GT(mean_value(alone), 0.01);  // a real image, not black
    ASSERT_GT(alone_stats.accumulation.photons_emitted, 0);  // with caustics
    EXPECT_EQ(alone_stats.accumulation.passes, 5);
    for (int ranks : {2, 3}) {
        const std::vector<RankOutcome> out = render_on_ranks(std::vector<RenderJob>(static_cast<std::size_t>(ranks), job));
        for (const RankOutcome& o : out) {
            EXPECT_TRUE(o.completed) << ranks << " ranks";
            EXPECT_FALSE(o.failure) << o.failure->message;
        }
        EXPECT_EQ(differing_pixels(out[0].image, alone), 0) << ranks << " ranks";
        EXPECT_EQ(out[0].stats.accumulation.passes, 5);
        EXPECT_EQ(out[0].stats.accumulation.photons_emitted, alone_stats.accumulation.photons_emitted);
        EXPECT_EQ(out[0].stats.accumulation.error, alone_stats.accumulation.error);
        // Every rank's samples counted once: the r_1 pass of the ranks that do not own pass 0 adds none.
        EXPECT_EQ(out[0].stats.rays.samples, alone_stats.rays.samples);
    }
}

// With a radius per pixel the factors change before passes 8 and 32, from every rank's sums: a
// round of ranks ends there, and 2 and 3 ranks still make one process's bits (3 ranks: rounds
// 0-2, 3-5, 6-7, 8-10, ...).
TEST(Cluster, AdaptedRadiiOnTwoAndThreeRanksAreOneProcesssBitForBit) {
    RenderJob job = caustic_box(IntegratorKind::progressive);
    job.options.adaptive_radius = true;
    job.options.passes = 35;
    RenderStats alone_stats;
    const Image alone = render_alone(job, &alone_stats);
    RenderJob fixed = job;
    fixed.options.adaptive_radius = false;
    ASSERT_GT(differing_pixels(render_alone(fixed), alone), 0);  // the factors changed the image
    expect_two_and_three_ranks_make(job, alone, alone_stats);
}

// With the balanced radius the whole sequence is scaled before passes 4, 8, 16 and 32 from the
// estimate of every rank's sums: rounds of ranks end there (3 ranks: 0-2, 3, 4-6, 7, 8-10, ...),
// every rank walks the sequence to the same pass before scaling it, and 2 and 3 ranks make one
// process's bits.
TEST(Cluster, BalancedRadiiOnTwoAndThreeRanksAreOneProcesssBitForBit) {
    RenderJob job = caustic_box(IntegratorKind::progressive);
    job.options.auto_radius = true;
    job.options.passes = 35;
    RenderStats alone_stats;
    const Image alone = render_alone(job, &alone_stats);
    RenderJob fixed = job;
    fixed.options.auto_radius = false;
    RenderStats fixed_stats;
    ASSERT_GT(differing_pixels(render_alone(fixed, &fixed_stats), alone), 0);  // the scale changed the image
    EXPECT_NE(fixed_stats.accumulation.radius, alone_stats.accumulation.radius);
    expect_two_and_three_ranks_make(job, alone, alone_stats);
}

TEST(Cluster, ProgressiveStopRulesDecideAlikeOnEveryRank) {
    // --target-error and --time with ranks: the estimate from every rank's sums, the slowest
    // rank's clock; every rank stops after the same pass.
    for (bool by_error : {true, false}) {
        RenderJob job = caustic_box(IntegratorKind::progressive);
        job.options.passes = 0;
        if (by_error)
            job.options.target_error = 0.25;
        else
            job.options.time_limit = 0.3;  // under ThreadSanitizer perhaps a single round: no pass count asserted
        const std::vector<RankOutcome> out = render_on_ranks({job, job, job});
        for (const RankOutcome& o : out) {
            ASSERT_TRUE(o.completed) << (o.failure ? o.failure->message : o.other_error);
            EXPECT_EQ(o.stats.accumulation.passes, out[0].stats.accumulation.passes);
            EXPECT_EQ(o.stats.accumulation.stopped_by, by_error ? "target error" : "time");
        }
        if (by_error) {
            EXPECT_GE(out[0].stats.accumulation.passes, 4);  // the rule waits for 4 passes
            EXPECT_GE(out[0].stats.accumulation.error, 0.0);
            EXPECT_LE(out[0].stats.accumulation.error, 0.25);
        }
    }
}

TEST(Cluster, ClassicImageWithPhotonsAndAntialiasingIsOneProcesssBitForBit) {
    RenderJob job = caustic_box(IntegratorKind::classic);
    job.options.caustic_num_photons = 400'000;  // a few hundred thousand: photons in many blocks
    RenderStats alone_stats;
    const Image alone = render_alone(job, &alone_stats);
    ASSERT_GT(mean_value(alone), 0.01);
    ASSERT_GT(alone_stats.caustic_photons, 1000u);
    ASSERT_GT(alone_stats.rays.supersampled_pixels, 0u);  // the anti-aliasing pass ran
    for (int ranks : {2, 3}) {
        const std::vector<RankOutcome> out = render_on_ranks(std::vector<RenderJob>(static_cast<std::size_t>(ranks), job));
        ASSERT_TRUE(out[0].completed) << (out[0].failure ? out[0].failure->message : out[0].other_error);
        EXPECT_EQ(differing_pixels(out[0].image, alone), 0) << ranks << " ranks";
        EXPECT_EQ(out[0].stats.caustic_photons, alone_stats.caustic_photons);
        EXPECT_EQ(out[0].stats.rays.supersampled_pixels, alone_stats.rays.supersampled_pixels);
        EXPECT_EQ(out[0].stats.rays.primary, alone_stats.rays.primary);
    }
}

TEST(Cluster, ClassicCornerGridAndGiMapsAreOneProcesss) {
    RenderJob job = caustic_box(IntegratorKind::classic);
    job.options.a4 = true;  // classic corner grid: the refine flags go to every rank with the first pass
    job.options.gi = true;
    job.options.gi_num_photons = 200'000;
    const Image alone = render_alone(job);
    const std::vector<RankOutcome> out = render_on_ranks({job, job});
    ASSERT_TRUE(out[0].completed);
    EXPECT_EQ(differing_pixels(out[0].image, alone), 0);
}

TEST(Cluster, MergedPhotonSharesAreOneProcesssMap) {
    // The unit under the classic split: shares shot by rank index merge to the single pass.
    ClassicPhotonResult a, b;
    a.caustic = {{{1, 0, 0}, {1, 1, 1}, {0, -1, 0}}, {{2, 0, 0}, {1, 1, 1}, {0, -1, 0}}};
    b.caustic = {{{3, 0, 0}, {1, 1, 1}, {0, -1, 0}}};
    const int blocks = classic_emission_blocks();
    a.caustic_blocks.assign(static_cast<std::size_t>(blocks), 0);
    b.caustic_blocks.assign(static_cast<std::size_t>(blocks), 0);
    a.caustic_blocks[0] = 1;  // block 0 (rank 0): photon 1; block 1 (rank 1): photon 3; block 2 (rank 0): photon 2
    b.caustic_blocks[1] = 1;
    a.caustic_blocks[2] = 1;
    a.caustic_lights.resize(1);
    b.caustic_lights.resize(1);
    a.caustic_lights[0].stored = 2;
    b.caustic_lights[0].stored = 1;
    const ClassicPhotonResult merged = merge_classic_photons({share_of(a), share_of(b)});
    ASSERT_EQ(merged.caustic.size(), 3u);
    EXPECT_EQ(merged.caustic[0].position.x, 1.0f);
    EXPECT_EQ(merged.caustic[1].position.x, 3.0f);
    EXPECT_EQ(merged.caustic[2].position.x, 2.0f);
    EXPECT_EQ(merged.caustic_lights[0].stored, 3);
    // A share that claims more photons than it holds is refused, not read past its end.
    ClassicPhotonResult d = b;
    d.caustic.clear();
    EXPECT_THROW(merge_classic_photons({share_of(a), share_of(d)}), std::runtime_error);
}

TEST(Cluster, ASceneErrorOnOneRankStopsEveryRankWithItsMessage) {
    for (IntegratorKind integrator : {IntegratorKind::classic, IntegratorKind::progressive}) {
        const RenderJob good = caustic_box(integrator);
        RenderJob bad = good;
        bad.options.caustic_num_photons = 4'000'000'000'000LL;  // more than any memory: refused on rank 1 only
        const std::vector<RankOutcome> out = render_on_ranks({good, bad, good});
        for (int r = 0; r < 3; ++r) {
            const RankOutcome& o = out[static_cast<std::size_t>(r)];
            ASSERT_TRUE(o.failure) << "rank " << r << ": " << o.other_error;
            EXPECT_EQ(o.failure->rank, 1);
            EXPECT_EQ(o.failure->exit_code, 2);
            EXPECT_NE(o.failure->message.find("--caustic-num-photons"), std::string::npos) << o.failure->message;
        }
    }
}

TEST(Cluster, SharedWorkIsDoneOnceAndAFailureMidwayStopsEveryRank) {
    // The tile loop's protocol alone: every item is worked exactly once and collected on rank 0;
    // when the rank given item 100 fails there, every rank returns that rank's failure and none
    // hangs.
    for (bool fail : {false, true}) {
        const int ranks = 3, items = 200;
        std::vector<std::unique_ptr<Cluster>> cluster = make_local_cluster(ranks);
        std::vector<int> collected(items, 0);
        std::vector<std::optional<RankFailure>> results(ranks);
        std::vector<std::thread> threads;
        for (int r = 0; r < ranks; ++r)
            threads.emplace_back([&, r] {
                const Cluster::WorkFn work = [&](int first, int last) {
                    if (fail && first <= 100 && 100 < last)
                        throw InputError("scene.lua:7: gr.render: broken on rank " + std::to_string(r));
                    Cluster::Bytes out;
                    for (int i = first; i < last; ++i) out.push_back(static_cast<std::uint8_t>(i % 251));
                    return out;
                };
                const Cluster::CollectFn collect = [&](int first, int last, const Cluster::Bytes& bytes) {
                    ASSERT_EQ(bytes.size(), static_cast<std::size_t>(last - first));
                    for (int i = first; i < last; ++i) {
                        EXPECT_EQ(bytes[static_cast<std::size_t>(i - first)], i % 251);
                        ++collected[static_cast<std::size_t>(i)];
                    }
                };
                results[static_cast<std::size_t>(r)] =
                    cluster[static_cast<std::size_t>(r)]->share_work(items, 4, work, collect, nullptr);
            });
        for (std::thread& t : threads) t.join();
        int once = 0;
        for (int c : collected) {
            EXPECT_LE(c, 1);
            once += c == 1;
        }
        for (const std::optional<RankFailure>& f : results) {
            ASSERT_EQ(f.has_value(), fail);
            if (f) {
                EXPECT_EQ(f->rank, results[0]->rank);
                EXPECT_EQ(f->exit_code, 2);
                EXPECT_EQ(f->message, "scene.lua:7: gr.render: broken on rank " + std::to_string(f->rank));
            }
        }
        if (fail) {
            EXPECT_EQ(collected[100], 0);  // the failed batch is not collected
        } else {
            EXPECT_EQ(once, items);
        }
    }
}

TEST(Cluster, InterruptingOneRankInterruptsEveryRank) {
    for (IntegratorKind integrator : {IntegratorKind::classic, IntegratorKind::progressive}) {
        RenderJob job = caustic_box(integrator);
        job.options.passes = 0;
        job.options.time_limit = 60.0;  // progressive: would run a minute
        job.options.resolution_override = 600;  // classic: about a second on one thread
        job.options.caustic_num_photons = 2'000'000;
        const auto t0 = std::chrono::steady_clock::now();
        const std::vector<RankOutcome> out = render_on_ranks({job, job}, [](int rank, RenderSession& session) {
            if (rank == 1) {
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
                session.cancel();
            }
        });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        for (const RankOutcome& o : out) {
            EXPECT_FALSE(o.completed);
            EXPECT_FALSE(o.failure) << o.failure->message;  // an interruption is not an error
            EXPECT_TRUE(o.other_error.empty()) << o.other_error;
        }
        EXPECT_LT(seconds, caustica::testing::time_bound(30.0));
    }
}

TEST(Cluster, AccumulatorSumsAreExactWhateverTheOrderAndSplit) {
    // The property the ranks rest on: the sums of passes added in any order, or split between
    // two accumulators and added up, are the same bits; a pixel that never changes has no noise.
    const int w = 4, passes = 37;
    auto sample = [](int pixel, int pass) {
        PassSample s;
        const float x = 1e-7f + 0.37f * static_cast<float>((pixel * 7919 + pass * 104729) % 1000) / 997.0f;
        s.colour = pixel == 0 ? glm::vec3(0.0003f) : glm::vec3(x, 2.5f * x, 1e4f * x);  // pixel 0: constant, dim
        s.photon = pixel == 0 ? 0.2 : static_cast<double>(x);
        s.photon_inner = pixel == 0 ? 0.2 : 0.9 * static_cast<double>(x);
        return s;
    };
    const caustica::testing::AccumulationOrders orders = caustica::testing::accumulate_in_three_orders(w, passes, sample);
    const ProgressiveAccumulator &forward = orders.forward, &backward = orders.backward;
    EXPECT_EQ(forward.sums(), backward.sums());
    EXPECT_EQ(forward.sums(), orders.merged);
    for (int i = 0; i < w; ++i) {
        const glm::vec3 a = forward.mean(static_cast<std::size_t>(i)), b = backward.mean(static_cast<std::size_t>(i));
        EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
        EXPECT_EQ(forward.samples(static_cast<std::size_t>(i)), static_cast<std::uint32_t>(passes));
    }
    // The mean is the float samples' mean to within the 2^-40 rounding of each sample.
    double sum = 0.0;
    for (int p = 0; p < passes; ++p) sum += sample(1, p).colour.z;
    EXPECT_NEAR(forward.mean(1).z, sum / passes, 1e-6 * sum / passes);
    // Only the constant pixel in the region: its estimated noise is exactly 0.
    ProgressiveAccumulator constant;
    constant.reset(1, 1);
    for (int p = 0; p < passes; ++p) constant.add(0, sample(0, p));
    const ErrorEstimate e = constant.estimate_error();
    ASSERT_TRUE(e.known);
    EXPECT_EQ(e.noise, 0.0);
}
