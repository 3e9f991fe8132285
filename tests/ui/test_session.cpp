// The render session as the preview drives it: cancelling in every stage, hundreds of parameter
// changes while rendering, no stale tile ever shown, no growth in memory, and picking from another
// thread. Small and GL-free, so that CI also runs it under ThreadSanitizer (session_tests).
#include "ui/preview_driver.h"
#include "core/photons/classic_photons.h"
#include "core/util/sanitized.h"

#include "tests/test_support.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <ostream>
#include <random>
#include <thread>
#include <unistd.h>

#if defined(__SANITIZE_THREAD__)
constexpr int work_divisor = 4;  // so the stage tests use smaller images and fewer photons
// ThreadSanitizer cannot see oneTBB's task hand-offs (the Debian libtbb is not instrumented):
// oneTBB runs on one thread here, and so does Embree's BVH build, which uses it. The renderer's
// own parallel loops run on threads the sanitizer sees (core/util/parallel.h), so tiles, photon
// blocks, grid, map and k-d tree builds still run concurrently, besides the preview's UI thread,
// the session's worker and a picking thread.
static const tbb::global_control one_tbb_thread(tbb::global_control::max_allowed_parallelism, 1);
#else
constexpr int work_divisor = 1;
#endif

namespace caustica::ui {
namespace {

using caustica::testing::JobBuilder;
using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

/// A floor, a diffuse ball and a mirror ball under a light with quadratic falloff; the camera
/// sees sky above the floor, whose miss colour tags each job: (0.25, id / 4096, 0.75).
JobBuilder lit_scene(int width, int height) {
    JobBuilder b(width, height);
    const int white = b.material({0.7, 0.7, 0.7});
    const int red = b.material({0.7, 0.2, 0.2});
    const int mirror = b.material({0.0, 0.0, 0.0}, {0.5, 0.5, 0.5}, 50.0, true);
    const int floor = b.add(NodeKind::cube, white);
    b.translate(floor, {0.0, -1.05, 0.0});
    b.scale(floor, {3.0, 0.05, 3.0});
    const int ball = b.add(NodeKind::sphere, red);
    b.translate(ball, {-0.6, -0.5, 0.0});
    b.scale(ball, {0.5, 0.5, 0.5});
    const int shiny = b.add(NodeKind::sphere, mirror);
    b.translate(shiny, {0.7, -0.5, -0.3});
    b.scale(shiny, {0.5, 0.5, 0.5});
    b.light({0.5, 2.5, 1.0}, {3.0, 3.0, 3.0}, {0.3, 0.0, 0.45});
    b.camera({0.0, 0.6, 5.0}, {0.0, -0.15, -1.0}, 45.0);
    b.job.ambient = {0.2, 0.2, 0.2};
    return b;
}

glm::dvec3 tag_colour(int id) { return {0.25, id / 4096.0, 0.75}; }

/// The job id of a sky pixel, or -1 when the pixel is not sky.
int sky_tag(const glm::vec3& p) { return p.x == 0.25f && p.z == 0.75f ? static_cast<int>(p.y * 4096.0f + 0.5f) : -1; }

/// A square grid of 2 n^2 triangles in the plane y = -1: a scene that takes a while to build.
std::shared_ptr<const MeshData> big_grid(int n) {
    auto mesh = std::make_shared<MeshData>();
    mesh->path = "grid";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) mesh->positions.push_back({-2.0f + 4.0f * i / n, -1.0f, -2.0f + 4.0f * j / n});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const unsigned a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            mesh->triangles.push_back({a, c, b});
            mesh->triangles.push_back({b, c, d});
        }
    return mesh;
}

/// Polls the session until its stage is `stage`; false when the render went past it.
bool wait_for_stage(const RenderSession& session, const std::string& stage, double seconds) {
    const auto t0 = clock_type::now();
    while (seconds_since(t0) < seconds) {
        const SessionProgress p = session.progress();
        if (p.running && p.stage == stage) return true;
        if (!p.running) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    return false;
}

/// Resident memory of this process in bytes.
double resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    double pages = 0.0, resident = 0.0;
    statm >> pages >> resident;
    return resident * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

struct StageCase {
    const char* stage;
    double stop_seconds;  ///< the bound on the worker stopping after cancel()
};

/// For gtest's test listing.
void PrintTo(const StageCase& c, std::ostream* os) { *os << c.stage; }

class CancelDuringStage : public ::testing::TestWithParam<StageCase> {};

TEST_P(CancelDuringStage, ReturnsAtOnceStopsSoonAndTheNextRenderIsWhole) {
    const StageCase c = GetParam();
    const std::string stage = c.stage;
    JobBuilder b = lit_scene(1024 / work_divisor, 768 / work_divisor);
    b.job.options.aa_threshold = 0.0;  // anti-alias every pixel that differs at all: a long last pass
    if (stage == "building the scene") {
        b.scene->meshes.push_back(big_grid(700));  // ~1M triangles
        const int grid = b.add(NodeKind::mesh, 0);
        b.scene->nodes[grid].mesh = 0;
    }
    if (stage == "shooting photons") {
        b.job.options.caustic_num_photons = 8'000'000 / (work_divisor * work_divisor);
        b.job.options.projection_map = ProjectionMapMode::off;  // trace every photon: a long pass
    } else {
        b.job.options.caustic_num_photons = 20000;
    }
    const RenderJob job = b.build();

    RenderSession session;
    if (stage == "preview") {
        // Photons not cached yet are shot after a coarse direct-light pass, cached ones before the
        // coarse pass: with them cached, the pass cut is the coarse pass and the photons stay.
        session.set_job(job);
        session.prepare();
    }
    // The coarse preview of this scene in 4 x 4 blocks lasts about 3 ms (either integrator): a
    // poller descheduled that long under a loaded ctest never sees the stage. Blocks of one pixel
    // make it about 50 ms; each tile still takes well under a millisecond, so the stop bound is
    // as demanding as before.
    session.set_coarse_preview(true, stage == "preview" ? 1 : preview_block);
    // A stage of a few tens of milliseconds can pass unseen by a poller that a loaded machine
    // deschedules that long: the render is started again (a whole new render, the same job)
    // until the poller sees it, a few times at most.
    bool seen = false;
    for (int attempt = 0; attempt < 5 && !seen; ++attempt) {
        session.set_job(job);
        session.start();
        seen = wait_for_stage(session, stage, caustica::testing::time_bound(60.0));
        if (!seen) session.wait();
    }
    ASSERT_TRUE(seen) << "never saw the stage '" << stage << "' in 5 renders";
    const auto t0 = clock_type::now();
    session.cancel();
    const double cancel_seconds = seconds_since(t0);
    while (session.progress().running) std::this_thread::sleep_for(std::chrono::microseconds(100));
    const double stop_seconds = seconds_since(t0);
    std::printf("[ cancel  ] %-18s cancel() %.3f ms, worker stopped after %.1f ms\n", c.stage, 1e3 * cancel_seconds,
                1e3 * stop_seconds);
    EXPECT_LT(cancel_seconds, caustica::testing::time_bound(0.001));
    EXPECT_LT(stop_seconds, caustica::testing::time_bound(c.stop_seconds));
    EXPECT_FALSE(session.wait());
    EXPECT_TRUE(session.progress().cancelled);

    const RenderSession::StageCounters before = session.stage_counters();
    session.set_job(job);
    session.start();
    EXPECT_TRUE(session.wait());
    const RenderSession::StageCounters after = session.stage_counters();
    // A finished BVH is kept even when its render was cancelled; a cut BVH build or photon pass is
    // not (a cancel during the scene build stops Embree's build, and the photon pass never starts).
    const bool build_cut = stage == "building the scene";
    const bool photons_cut = stage == "shooting photons" || build_cut;
    EXPECT_EQ(after.scene_builds, before.scene_builds + (build_cut ? 1 : 0));
    EXPECT_EQ(after.photon_passes, before.photon_passes + (photons_cut ? 1 : 0));
    if (stage != "building the scene" && stage != "shooting photons") {
        RenderSession fresh;
        fresh.set_job(job);
        fresh.start();
        ASSERT_TRUE(fresh.wait());
        EXPECT_EQ(session.image().pixels, fresh.image().pixels);  // reproducible: nothing left of the cut render
    }
}

// A pass stops within a frame (16 ms); Embree stops a BVH build at its next progress report
// (docs/PERFORMANCE.md has its time on a million triangles); the k-d tree of the photons shot so
// far cannot be interrupted, so that stage gets a longer bound (the UI never waits for it).
INSTANTIATE_TEST_SUITE_P(Stages, CancelDuringStage,
                         ::testing::Values(StageCase{"building the scene", 0.25}, StageCase{"shooting photons", 5.0},
                                           StageCase{"preview", 0.016}, StageCase{"first samples", 0.016},
                                           StageCase{"anti-aliasing", 0.016}),
                         [](const auto& info) {
                             std::string name = info.param.stage;
                             for (char& ch : name)
                                 if (ch == ' ' || ch == '-') ch = '_';
                             return name;
                         });

TEST(PreviewDriver, HundredsOfChangesWhileRenderingShowNoStaleTile) {
    JobBuilder b = lit_scene(192, 144);
    b.job.options.caustic_num_photons = 20000;
    b.job.options.reproducible = true;
    RenderJob job = b.build();
    PreviewDriver driver;
    std::mt19937 random(5);
    int id = 1;
    std::size_t tiles_checked = 0;
    std::map<std::uint64_t, int> tag_of_generation;  // which job each started render drew
    std::uint64_t newest_copied = 0;
    const auto check_tiles = [&] {
        tag_of_generation[driver.generation()] = sky_tag(glm::vec3(driver.job().miss_colour));
        const Image& image = driver.image();
        const std::vector<std::size_t>& changed = driver.changed_tiles();
        for (std::size_t k = 0; k < changed.size(); ++k) {
            const std::size_t t = changed[k];
            const std::uint64_t generation = driver.changed_generations()[k];
            // Copies come from ever newer renders, never from one older than a copy before.
            ASSERT_GE(generation, newest_copied);
            newest_copied = generation;
            if (std::find(changed.begin() + k + 1, changed.end(), t) != changed.end()) continue;  // copied again since
            ASSERT_TRUE(tag_of_generation.count(generation));
            const int expected = tag_of_generation[generation];
            const Tile& tile = driver.tiles()[t];
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const int tag = sky_tag(image.at(x, y));
                    ASSERT_TRUE(tag == -1 || tag == expected)
                        << "tile " << t << " of render " << generation << " shows job " << tag << ", not " << expected;
                }
            ++tiles_checked;
        }
    };
    for (int step = 0; step < 400; ++step) {
        job.miss_colour = tag_colour(++id);
        switch (random() % 6) {
        case 0: job.camera.eye.x += 0.01; break;
        case 1: job.options.caustic_num_neighbours = 20 + static_cast<int>(random() % 100); break;
        case 2: job.options.caustic_max_dist = 0.05 + 0.01 * (random() % 10); break;
        case 3: job.options.caustic_num_photons = 10000 + 1000 * (random() % 20); break;
        case 4: job.width = (random() % 2) ? 192 : 160; break;
        default: job.options.threads = 1 + static_cast<int>(random() % 2); break;
        }
        driver.request(job);
        driver.update();
        check_tiles();
        if (HasFatalFailure()) return;
        std::this_thread::sleep_for(std::chrono::microseconds(random() % 3000));
        driver.update();
        check_tiles();
        if (HasFatalFailure()) return;
    }
    const auto t0 = clock_type::now();
    while (!driver.finished() && seconds_since(t0) < caustica::testing::time_bound(60.0)) {
        driver.update();
        check_tiles();
        if (HasFatalFailure()) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(driver.finished());
    EXPECT_GT(tiles_checked, 0u);
    // Every tile of the shown image is the last job's, exactly as a render of it alone.
    RenderSession reference;
    reference.set_job(job);
    reference.start();
    ASSERT_TRUE(reference.wait());
    EXPECT_EQ(driver.image().pixels, reference.image().pixels);
    std::printf("[ restarts] %llu renders started, longest restart %.2f ms, %zu tiles checked\n",
                static_cast<unsigned long long>(driver.restarts()), 1e3 * driver.longest_restart_seconds(), tiles_checked);
    EXPECT_LT(driver.longest_restart_seconds(), caustica::testing::time_bound(0.016));
    EXPECT_FALSE(driver.take_error().has_value());
}

TEST(PreviewDriver, MemoryStaysFlatOverManyRestarts) {
    JobBuilder b = lit_scene(256, 192);
    b.job.options.caustic_num_photons = 50000;
    RenderJob job = b.build();
    PreviewDriver driver;
    auto churn = [&](int steps) {
        for (int i = 0; i < steps; ++i) {
            job.camera.eye.x = 0.001 * (i % 50);
            job.options.caustic_num_photons = 50000 + (i % 3) * 1000;  // re-shoot, new maps
            driver.request(job);
            for (int k = 0; k < 3; ++k) {
                driver.update();
                std::this_thread::sleep_for(std::chrono::microseconds(500));
            }
        }
        while (!driver.finished()) {
            driver.update();
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    };
    churn(60);  // warm up: allocator pools, TBB threads, the image
    const double before = resident_bytes();
    churn(300);
    const double growth = resident_bytes() - before;
    std::printf("[ memory  ] resident growth over 300 restarts: %.1f MiB\n", growth / 1048576.0);
    // One leaked image or photon map per restart would be > 100 MiB here.
    EXPECT_LT(growth, 24.0 * 1048576.0 * (caustica::sanitized_build ? 4.0 : 1.0));
}

TEST(PreviewDriver, PickFromAnotherThreadWhileScenesAreRebuilt) {
    JobBuilder b = lit_scene(128, 96);
    RenderJob job = b.build();
    PreviewDriver driver;
    std::atomic<bool> stop{false};
    std::atomic<int> hits{0};
    std::thread picker([&] {  // as the overlay tracer does
        const Ray down{{0.0f, 3.0f, 0.5f}, {0.0f, -1.0f, 0.0f}, 0.0f, ray_infinity};
        while (!stop) {
            glm::vec3 p;
            if (driver.session().pick(down, p)) ++hits;
        }
    });
    auto scene = std::make_shared<SceneDesc>(*job.scene);
    for (int i = 0; i < 60; ++i) {
        scene = std::make_shared<SceneDesc>(*scene);
        scene->nodes[1].transforms[0].amount.y = -1.05 + 0.001 * i;  // the floor moves: a new BVH
        job.scene = scene;
        driver.request(job);
        for (int k = 0; k < 5; ++k) {
            driver.update();
            std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
    }
    while (!driver.finished()) {
        driver.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    stop = true;
    picker.join();
    EXPECT_GT(hits.load(), 0);
    EXPECT_GT(driver.session().stage_counters().scene_builds, 1);
}

TEST(PreviewDriver, DestroyingTheDriverWhileRenderingReturnsPromptly) {
    JobBuilder b = lit_scene(1024, 768);
    b.job.options.aa_threshold = 0.0;
    // The bounds first: measuring the machine takes a few tenths of a second, long enough for the
    // render to be past its first samples if it ran after the request.
    const double start_bound = caustica::testing::time_bound(30.0), stop_bound = caustica::testing::time_bound(0.05);
    auto driver = std::make_unique<PreviewDriver>();
    driver->request(b.build());
    driver->update();
    ASSERT_TRUE(wait_for_stage(driver->session(), "first samples", start_bound));
    const auto t0 = clock_type::now();
    driver.reset();
    EXPECT_LT(seconds_since(t0), stop_bound);
}

/// Updates the driver (about every millisecond) until `done` or `seconds` pass; returns `done()`.
bool update_until(PreviewDriver& driver, const std::function<bool()>& done, double seconds) {
    const auto t0 = clock_type::now();
    while (!done() && seconds_since(t0) < seconds) {
        driver.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return done();
}

TEST(PreviewDriver, AccumulationPausesResumesAndTakesNewStopRulesWithoutStartingAgain) {
    JobBuilder b = lit_scene(96, 72);
    b.job.options.caustic_num_photons = 5000;
    b.job.options.integrator = IntegratorKind::progressive;
    b.job.options.passes = 0;  // until paused
    b.job.options.target_error = 0.0;
    PreviewDriver driver;
    driver.request(b.build());
    const SessionProgress& a = driver.accumulation();
    ASSERT_TRUE(update_until(driver, [&] { return a.passes_done >= 4; }, caustica::testing::time_bound(20.0)));
    EXPECT_TRUE(driver.first_full_pass_done() && driver.maps_final() && driver.busy());
    EXPECT_FALSE(driver.finished());

    driver.pause();
    ASSERT_TRUE(update_until(driver, [&] { return !driver.busy(); }, caustica::testing::time_bound(5.0)));
    EXPECT_TRUE(driver.paused());
    const int paused_at = a.passes_done;
    const std::vector<glm::vec3> shown = driver.image().pixels;
    update_until(driver, [] { return false; }, 0.3);
    EXPECT_EQ(a.passes_done, paused_at);
    EXPECT_EQ(driver.image().pixels, shown);

    driver.resume();
    int lowest = paused_at;
    ASSERT_TRUE(update_until(driver, [&] {
        lowest = std::min(lowest, a.passes_done);
        return a.passes_done >= paused_at + 2;
    }, caustica::testing::time_bound(20.0)));
    EXPECT_EQ(lowest, paused_at);

    // A pass limit below what is done stops at once; a higher one continues to it.
    driver.set_stop_rules({a.passes_done, 0.0, 0.0});
    ASSERT_TRUE(update_until(driver, [&] { return driver.finished(); }, caustica::testing::time_bound(5.0)));
    const int stopped_at = a.passes_done;
    EXPECT_EQ(a.stopped_by, "passes");
    driver.set_stop_rules({stopped_at + 2, 0.0, 0.0});
    ASSERT_TRUE(update_until(driver, [&] { return driver.finished() && a.passes_done == stopped_at + 2; },
                             caustica::testing::time_bound(20.0)));
    EXPECT_EQ(driver.job().options.passes, stopped_at + 2);
    EXPECT_EQ(driver.restarts(), 1u);  // one render started; the rest resumed it
    const RenderSession::StageCounters counters = driver.session().stage_counters();
    EXPECT_EQ(counters.scene_builds, 1);
    EXPECT_EQ(counters.photon_passes, 1);  // the first pass's photons; later passes are fresh but not a stage
    EXPECT_FALSE(driver.take_error().has_value());
}

TEST(PreviewDriver, ARequestWhilePausedIsRenderedAndEndsThePause) {
    JobBuilder b = lit_scene(96, 72);
    b.job.options.caustic_num_photons = 5000;
    b.job.options.integrator = IntegratorKind::progressive;
    b.job.options.passes = 0;
    RenderJob job = b.build();
    PreviewDriver driver;
    driver.request(job);
    ASSERT_TRUE(update_until(driver, [&] { return driver.accumulation().passes_done >= 2; }, caustica::testing::time_bound(20.0)));
    driver.pause();
    ASSERT_TRUE(update_until(driver, [&] { return !driver.busy(); }, caustica::testing::time_bound(5.0)));
    job.camera.eye.x += 0.1;
    driver.request(job);
    ASSERT_TRUE(update_until(driver, [&] { return driver.restarts() == 2 && driver.accumulation().passes_done >= 1; },
                             caustica::testing::time_bound(20.0)));
    EXPECT_FALSE(driver.paused());
    EXPECT_EQ(driver.job().camera.eye.x, job.camera.eye.x);
    EXPECT_EQ(driver.session().stage_counters().photon_passes, 1);  // the camera keeps the photons
}

TEST(PreviewDriver, ARenderErrorIsReportedOnceAndTheDriverGoesOn) {
    JobBuilder b = lit_scene(64, 48);
    b.job.options.caustic_num_photons = 1000;
    // The progressive integrator refuses a surface that would make energy (its photons need
    // kd + ks <= 1); the classic one draws its odds from the lumas and absorbs the rest.
    b.job.options.integrator = IntegratorKind::progressive;
    b.scene->materials[2].kd = {0.9, 0.9, 0.9};  // the mirror: mean(kd) + mean(ks) = 1.4 > 1
    PreviewDriver driver;
    driver.request(b.build());
    std::optional<std::string> error;
    const auto t0 = clock_type::now();
    while (!error && seconds_since(t0) < caustica::testing::time_bound(10.0)) {
        driver.update();
        error = driver.take_error();
    }
    ASSERT_TRUE(error.has_value());
    EXPECT_NE(error->find("exceeds 1"), std::string::npos) << *error;
    EXPECT_FALSE(driver.take_error().has_value());
    b.scene->materials[2].kd = {0.0, 0.0, 0.0};
    driver.request(b.build());
    while (!driver.finished() && seconds_since(t0) < caustica::testing::time_bound(20.0)) driver.update();
    EXPECT_TRUE(driver.finished());
}

/// The share of pixels with some light in them (any channel above 1/100).
double lit_share(const Image& image) {
    if (image.pixels.empty()) return 0.0;
    const auto lit = std::count_if(image.pixels.begin(), image.pixels.end(), [](const glm::vec3& p) {
        return p.x > 0.01f || p.y > 0.01f || p.z > 0.01f;
    });
    return static_cast<double>(lit) / static_cast<double>(image.pixels.size());
}

/// What a classic render in the driver showed while its photons were shot.
struct PhotonStageWatch {
    bool direct_light_shown = false;  ///< a lit image was on screen during the photon stage
    std::string label;                ///< the status's words for the stage then
    std::vector<double> fractions;    ///< render_fraction() over the photon stage, in order
    double darkest = 1.0;             ///< the least lit share of the image shown at any update
    bool photons_shot = false;        ///< the photon stage was seen at all
};

/// Updates the driver until its render finishes, watching the photon stage. The session's
/// progress is read after each update's copy: a copy made while the session is still shooting
/// photons holds only tiles published before the photon stage ended.
PhotonStageWatch watch_until_finished(PreviewDriver& driver, double seconds) {
    PhotonStageWatch watch;
    const auto t0 = clock_type::now();
    while (!driver.finished() && seconds_since(t0) < seconds) {
        driver.update();
        const SessionProgress now = driver.session().progress();
        if (now.running && now.stage == "shooting photons") {
            watch.photons_shot = true;
            watch.fractions.push_back(render_fraction(now));
            if (!watch.direct_light_shown && now.showing_direct_light && lit_share(driver.image()) > 0.0) {
                watch.direct_light_shown = true;
                watch.label = running_stage(now);
            }
        }
        if (driver.has_job() && !driver.image().pixels.empty())
            watch.darkest = std::min(watch.darkest, lit_share(driver.image()));
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    return watch;
}

TEST(PreviewDriver, ClassicShowsDirectLightWhilePhotonsAreShotThenTheBatchImage) {
    JobBuilder b = lit_scene(128, 96);
    b.job.ambient = {0.0, 0.0, 0.0};
    b.job.miss_colour = {0.0, 0.0, 0.0};  // a pixel with light in it was lit by the light
    const long long photons = 600'000 / (work_divisor * work_divisor);
    b.job.options.caustic_num_photons = photons;
    b.job.options.projection_map = ProjectionMapMode::off;  // every photon traced: a stage to watch
    RenderJob job = b.build();
    ASSERT_EQ(job.options.integrator, IntegratorKind::classic);

    PreviewDriver driver;
    driver.request(job);
    const PhotonStageWatch launch = watch_until_finished(driver, caustica::testing::time_bound(60.0));
    ASSERT_TRUE(driver.finished());
    ASSERT_TRUE(launch.photons_shot);
    // The first image came while the photons were shot: direct light, labelled as such.
    EXPECT_TRUE(launch.direct_light_shown);
    EXPECT_EQ(launch.label, "direct light; shooting photons");
    // The photon progress counts every direction the cells offer, rising from 0 to 1.
    const SessionProgress end = driver.session().progress();
    EXPECT_EQ(end.photons_total, classic_photons_offered(photons));
    EXPECT_EQ(end.photons_done, end.photons_total);
    EXPECT_FALSE(end.showing_direct_light);
    EXPECT_TRUE(std::is_sorted(launch.fractions.begin(), launch.fractions.end()));
    const auto under_way = [](double f) { return f > 0.0 && f < 1.0; };
    EXPECT_TRUE(std::any_of(launch.fractions.begin(), launch.fractions.end(), under_way))
        << "no fraction between 0 and 1 in " << launch.fractions.size() << " updates";
    // The direct-light pass never reaches the batch image: it is the batch render's, bit for bit.
    RenderSession batch;
    batch.set_job(job);
    batch.start();
    ASSERT_TRUE(batch.wait());
    EXPECT_EQ(driver.image().pixels, batch.image().pixels);
    const double final_lit = lit_share(batch.image());
    ASSERT_GT(final_lit, 0.2);

    // Another photon count: shot again with their progress, over a lit image all along.
    job.options.caustic_num_photons = photons + photons / 4;
    driver.request(job);
    const PhotonStageWatch change = watch_until_finished(driver, caustica::testing::time_bound(60.0));
    ASSERT_TRUE(driver.finished());
    EXPECT_TRUE(change.photons_shot);
    EXPECT_TRUE(change.direct_light_shown);
    EXPECT_GT(change.darkest, 0.5 * final_lit) << "the image went dark while the photons were shot";
    EXPECT_EQ(driver.session().progress().photons_total, classic_photons_offered(job.options.caustic_num_photons));
    EXPECT_EQ(driver.session().stage_counters().photon_passes, 2);

    // A camera move keeps the photons: no photon stage, no direct-light pass.
    job.camera.eye.x += 0.2;
    driver.request(job);
    const PhotonStageWatch move = watch_until_finished(driver, caustica::testing::time_bound(60.0));
    ASSERT_TRUE(driver.finished());
    EXPECT_FALSE(move.photons_shot);
    EXPECT_FALSE(driver.session().progress().showing_direct_light);
    EXPECT_EQ(driver.session().stage_counters().photon_passes, 2);
    EXPECT_FALSE(driver.take_error().has_value());
}

}  // namespace
}  // namespace caustica::ui
