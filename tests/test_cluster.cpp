// Rendering one frame on several ranks (issue 13), with threads standing in for the ranks
// (make_local_cluster: the protocol the MPI ranks follow, in one process, so that it runs under
// the sanitizers too). The image of K ranks is one process's, bit for bit, for both integrators;
// a failure or an interruption on one rank stops every rank with that rank's message. The same
// with real processes under mpirun: test_mpi.cpp.
#include "core/lua/scene_loader.h"
#include "core/photons/classic_photons.h"
#include "core/render/cluster.h"
#include "core/render/render_session.h"
#include "core/scene/source_location.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <limits>
#include <functional>
#include <string>
#include <thread>

using namespace caustica;

namespace {

RenderJob caustic_box(IntegratorKind integrator) {
    static const SceneScript script = load_scene_script(CAUSTICA_SOURCE_DIR "/tests/ui/scenes/caustic_box.lua");
    RenderJob job = script.renders.at(0);
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

}  // namespace

TEST(Cluster, ProgressiveImageOnTwoAndThreeRanksIsOneProcesssBitForBit) {
    const RenderJob job = caustic_box(IntegratorKind::progressive);
    RenderStats alone_stats;
    const Image alone = render_alone(job, &alone_stats);
    ASSERT_GT(mean_value(alone), 0.01);  // a real image, not black
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
    job.options.a4 = true;  // B3's corner grid: the refine flags go to every rank with the first pass
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
    std::vector<ClassicPhotonResult> shares;
    shares.push_back(a);
    shares.push_back(b);
    const ClassicPhotonResult merged = merge_classic_photons(std::move(shares));
    ASSERT_EQ(merged.caustic.size(), 3u);
    EXPECT_EQ(merged.caustic[0].position.x, 1.0f);
    EXPECT_EQ(merged.caustic[1].position.x, 3.0f);
    EXPECT_EQ(merged.caustic[2].position.x, 2.0f);
    EXPECT_EQ(merged.caustic_lights[0].stored, 3);
    // A share that claims more photons than it holds is refused, not read past its end.
    ClassicPhotonResult c = a, d = b;
    d.caustic.clear();
    std::vector<ClassicPhotonResult> broken;
    broken.push_back(c);
    broken.push_back(d);
    EXPECT_THROW(merge_classic_photons(std::move(broken)), std::runtime_error);
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
        if (!fail) EXPECT_EQ(once, items);
        if (fail) EXPECT_EQ(collected[100], 0);  // the failed batch is not collected
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
        EXPECT_LT(seconds, 30.0);
    }
}
