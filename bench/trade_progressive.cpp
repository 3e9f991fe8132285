// Progressive curves and pixel-averaged references of bench/trade (see trade_progressive.h).
#include "bench/trade_progressive.h"

#include "bench/primary_rays.h"
#include "bench/trade_reference.h"
#include "core/io/png_io.h"
#include "core/lua/scene_loader.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_session.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "tests/test_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace caustica::trade {

namespace fs = std::filesystem;

const std::vector<ProgressiveRecipe> progressive_recipes = {
    // 512 x 512, the size of the targets. The radius is fixed (--radius-alpha 1) at 0.3 pixel
    // footprints, so the reference's blur is that of a 0.3-footprint disc, about a seventh of what
    // a 20 s run at 1.5 footprints averages over its passes (blur goes as r^2), and its noise falls
    // as 1 / sqrt(passes); each pass shoots 15x the scene's own photons, so that a disc that small
    // still holds photons. ACCURACY.md gives the times and the references' own errors.
    {"default", 512, 512, 150'000'000, 0.3, 0.15, 800},
    {"glass_of_liquid", 512, 512, 300'000'000, 0.3, 0.15, 800},
};

namespace {

const std::string source_dir = CAUSTICA_SOURCE_DIR;
const std::string reference_dir = "assets/references";

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Render time of the last start/resume of an accumulating session: its photon stages and image
/// passes, without the scene build.
double segment_seconds(const RenderStats& stats) {
    double seconds = 0.0;
    for (const StageTime& s : stats.stages)
        if (s.name == "projection maps" || s.name == "photon shooting" || s.name == "photon k-d tree" ||
            s.name == "progressive passes" || s.name == "photon passes")
            seconds += s.seconds;
    return seconds;
}

/// Starts (or resumes) the accumulation until `passes` passes; returns the segment's render time.
double run_until(RenderSession& session, int passes, bool first) {
    // passes = 1 alone is the single k-nearest pass: a time limit no run reaches makes it accumulate.
    session.set_stop_rules(passes, 1e9, 0.0);
    if (first) session.start();
    else if (!session.resume()) throw std::runtime_error("progressive: cannot resume the accumulation");
    if (!session.wait()) throw std::runtime_error("render cancelled");
    return segment_seconds(session.stats());
}

const ReferenceRecipe& lua_recipe(const char* name) {
    for (const ReferenceRecipe& r : recipes)
        if (std::string(r.name) == name) return r;
    throw std::runtime_error(std::string("no scene recipe named ") + name);
}

RenderJob progressive_job(const ProgressiveRecipe& recipe, int threads) {
    RenderJob job = load_lua_job(lua_recipe(recipe.name), threads);
    job.width = recipe.width;
    job.height = recipe.height;
    return job;
}

ReferenceInfo expected_progressive_info(const ProgressiveRecipe& recipe) {
    return recipe_info(lua_recipe(recipe.name).script, progressive_job(recipe, 1), recipe.photons,
                       static_cast<int>(std::lround(recipe.radius * 1000.0)), recipe.max_dist, recipe.passes);
}

std::string progressive_base(const ProgressiveRecipe& recipe) {
    return source_dir + "/" + reference_dir + "/" + recipe.name + "_progressive";
}

}  // namespace

double log_log_slope(const std::vector<std::pair<double, double>>& points) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(points.size());
    for (const auto& [x, y] : points) {
        const double lx = std::log10(x), ly = std::log10(y);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    const double d = n * sxx - sx * sx;
    return d > 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

std::vector<ProgressivePoint> progressive_curve(const TradeScene& scene, const ProgressiveRun& run) {
    RenderJob job = scene.job;
    if (run.photons > 0) job.options.caustic_num_photons = run.photons;
    if (run.radius > 0.0) job.options.accumulation_radius = run.radius;
    if (run.max_dist > 0.0) job.options.caustic_max_dist = run.max_dist;
    if (run.split) job.options.photon_split = true;
    if (run.adaptive_radius) job.options.adaptive_radius = true;
    if (run.auto_radius) job.options.auto_radius = true;
    if (run.guided_emission >= 0) job.options.guided_emission = run.guided_emission == 1;
    job.options.photons_per_pixel = run.photons_per_pixel;
    job.options.passes = 1;
    job.options.time_limit = 1e9;
    RenderSession session;
    session.set_job(job);
    std::vector<ProgressivePoint> points;
    double seconds = 0.0;
    for (int passes = 1;; passes = std::min(2 * passes, run.max_passes)) {
        seconds += run_until(session, passes, points.empty());
        const RenderStats stats = session.stats();
        ProgressivePoint p;
        p.passes = stats.accumulation.passes;
        p.seconds = seconds;
        p.error = compare_images(session.image(), scene.reference, scene.region);
        p.rel_rmse_less_noise = std::sqrt(std::max(0.0, p.error.rel_rmse * p.error.rel_rmse -
                                                            scene.reference_noise * scene.reference_noise));
        p.estimate = stats.accumulation.error;
        p.noise = stats.accumulation.noise;
        p.bias = stats.accumulation.bias;
        p.first_radius = stats.accumulation.first_radius;
        p.radius = stats.accumulation.radius;
        p.photons_emitted = stats.accumulation.photons_emitted;
        points.push_back(p);
        std::printf("%-16s %6d passes %9.3f s  rel %.4f (%.4f less the reference's noise)  bias %+.4f  estimate %s "
                    "(noise %.4f bias %.4f)  radius %.4f -> %.4f\n",
                    scene.name.c_str(), p.passes, p.seconds, p.error.rel_rmse, p.rel_rmse_less_noise, p.error.rel_bias,
                    p.estimate < 0.0 ? "  --  " : std::to_string(p.estimate).substr(0, 6).c_str(), p.noise, p.bias,
                    p.first_radius, p.radius);
        std::fflush(stdout);
        if (passes >= run.max_passes || (run.max_seconds > 0.0 && seconds >= run.max_seconds)) break;
    }
    if (!run.png_path.empty()) write_png_atomic(run.png_path, session.image(), PixelEncoding::clamped_linear);
    return points;
}

Image pixel_averaged_virtual_light(const TradeScene& scene, int passes, int threads) {
    caustica::testing::JobBuilder truth = caustica::testing::virtual_light_scene(true);
    truth.job.width = scene.job.width;
    truth.job.height = scene.job.height;
    truth.job.options.threads = threads;
    truth.job.options.integrator = IntegratorKind::progressive;
    truth.job.options.passes = passes;  // nothing specular: jittered direct light only
    truth.job.miss_colour = glm::dvec3(0.0);
    return caustica::testing::render(truth.build());
}

void make_progressive_reference(const ProgressiveRecipe& recipe, int threads) {
    // Two independent accumulations (seeds 1 and 2) of passes / 2 each: their mean is the
    // reference, half their difference its own error (as the stored k-nearest references do).
    const double t0 = now_seconds();
    RenderJob job = progressive_job(recipe, threads);
    job.options.caustic_num_photons = recipe.photons;
    job.options.accumulation_radius = recipe.radius;
    job.options.radius_alpha = 1.0;
    job.options.caustic_max_dist = recipe.max_dist;
    Image halves[2];
    double estimates[2] = {0.0, 0.0};
    for (int half = 0; half < 2; ++half) {
        job.options.seed = half + 1;
        RenderSession session;
        session.set_job(job);
        bool first = true;
        for (int passes = 16;; passes = std::min(2 * passes, recipe.passes / 2)) {
            run_until(session, passes, first);
            first = false;
            const RenderStats::Accumulation a = session.stats().accumulation;
            std::printf("  %s: seed %d, %d/%d passes, %.0f s, estimated error %.4f (noise %.4f, bias %.4f), "
                        "radius %.4f -> %.4f\n",
                        recipe.name, half + 1, a.passes, recipe.passes / 2, now_seconds() - t0, a.error, a.noise, a.bias,
                        a.first_radius, a.radius);
            std::fflush(stdout);
            if (passes >= recipe.passes / 2) break;
        }
        halves[half] = session.image();
        estimates[half] = session.stats().accumulation.error;
    }
    Image mean = halves[0];
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = 0.5f * (halves[0].pixels[i] + halves[1].pixels[i]);
    ReferenceInfo info = expected_progressive_info(recipe);
    // The halves' difference has 4x the variance of the mean's error: halve its RMSE.
    info.noise = 0.5 * compare_images(halves[0], halves[1], caustic_region(mean)).rel_rmse;
    info.seconds = now_seconds() - t0;
    info.command = std::string("build/trade --make-references --progressive --scenes ") + recipe.name;
    const std::string base = progressive_base(recipe);
    fs::create_directories(source_dir + "/" + reference_dir);
    write_pfm(base + ".pfm", mean);
    write_reference_info(base + ".txt", info);
    std::printf("  %s: wrote %s.pfm in %.0f s: own noise %.4f relative RMSE over the caustic region (from the two "
                "halves; the renderer estimated %.4f and %.4f for each half)\n",
                recipe.name, base.c_str(), info.seconds, info.noise, estimates[0], estimates[1]);
}

/// Seconds Embree alone takes to trace `rays` rays on `threads` threads, at the rate it traces the
/// job's primary rays (one per pixel centre, nothing else: the ray-casting rate the image pass is
/// held against), in 8-wide coherent packets and one ray at a time. Best of three timings of the
/// whole image each, on one build of the scene.
struct EmbreeAlone {
    double packets = 0.0, single = 0.0;
};
EmbreeAlone embree_alone_seconds(const RenderJob& job, std::uint64_t rays, int threads) {
    const RenderScene scene(*job.scene, flatten_scene(*job.scene, job.root, true));
    const Camera camera(job.camera, job.width, job.height);
    RTCScene embree = scene.embree_scene();
    auto seconds = [&](bool packets) {
        auto rows = [&](int y0, int y1, unsigned& hits) {
            RayQueryContext context;  // its user-geometry callbacks read one
            for (int y = y0; y < y1; ++y) {
                if (packets)
                    for (int x = 0; x < job.width; x += 8) hits += bench::trace_primary_packet(embree, context, camera, x, y, job.width);
                else
                    for (int x = 0; x < job.width; ++x) hits += bench::trace_primary_ray(embree, context, camera, x, y);
            }
        };
        double best = 1e30;
        for (int attempt = 0; attempt < 3; ++attempt) {
            std::vector<unsigned> hits(static_cast<std::size_t>(threads), 0);
            std::vector<std::thread> workers;
            const double t0 = now_seconds();
            for (int t = 0; t < threads; ++t)
                workers.emplace_back(rows, job.height * t / threads, job.height * (t + 1) / threads, std::ref(hits[t]));
            for (std::thread& w : workers) w.join();
            best = std::min(best, now_seconds() - t0);
        }
        return best / (static_cast<double>(job.width) * job.height) * static_cast<double>(rays);
    };
    return {seconds(true), seconds(false)};
}

void pass_timing(const char* scene_name, int width, int height, int passes, int threads) {
    const ReferenceRecipe& recipe = lua_recipe(scene_name);
    RenderJob job = load_scene_script(source_dir + "/" + recipe.script).renders.at(0);
    job.width = width;
    job.height = height;
    job.options.resolution_override = 0;
    job.options.integrator = IntegratorKind::progressive;
    job.options.threads = threads;
    job.options.passes = passes;
    job.options.silent = true;
    job.options.stats = job.options.timing = job.options.verbose = false;
    RenderSession session;
    session.set_job(job);
    const double t0 = now_seconds();
    session.start();
    if (!session.wait()) throw std::runtime_error("render cancelled");
    const double wall = now_seconds() - t0;
    const RenderStats stats = session.stats();
    double first_photons = 0.0, later_photons = 0.0, images = 0.0, build = 0.0;
    for (const StageTime& st : stats.stages) {
        if (st.name == "projection maps" || st.name == "photon shooting" || st.name == "photon k-d tree")
            first_photons += st.seconds;
        else if (st.name == "photon passes") later_photons += st.seconds;
        else if (st.name == "progressive passes") images += st.seconds;
        else build += st.seconds;
    }
    const long long traced = stats.caustic_lights.empty() ? 0 : stats.caustic_lights[0].traced;
    const double n = static_cast<double>(stats.accumulation.passes);
    std::printf("%s at %dx%d, %d threads, %d passes of %lld photon directions (N %d): wall %.2f s (other stages %.3f s)\n"
                "  per pass: %.3f s = photons %.3f s (first pass %.3f s, later passes %.3f s each) + image %.3f s\n"
                "  photons traced a pass %lld (%.1f M traced/s in the later photon stages), %.0f M directions/s\n"
                "  radiance estimates: %.3f s summed over threads, %.0f%% of the image passes' thread time\n",
                scene_name, width, height, threads, stats.accumulation.passes, job.options.caustic_num_photons,
                job.options.caustic_num_neighbours, wall, build, (first_photons + later_photons + images) / n,
                (first_photons + later_photons) / n, first_photons, n > 1 ? later_photons / (n - 1) : 0.0, images / n,
                traced, n > 1 && later_photons > 0 ? static_cast<double>(traced) * (n - 1) / later_photons / 1e6 : 0.0,
                n > 1 && later_photons > 0 ? static_cast<double>(job.options.caustic_num_photons) * (n - 1) / later_photons / 1e6 : 0.0,
                stats.rays.gather_seconds, 100.0 * stats.rays.gather_seconds / (images * threads));
    const RayCounters& r = stats.rays;
    const std::uint64_t rays = r.total_rays();
    const auto per_pass = static_cast<std::uint64_t>(static_cast<double>(rays) / std::max(1.0, n));
    const EmbreeAlone alone = embree_alone_seconds(job, per_pass, threads);
    const double image = images / std::max(1.0, n);
    std::printf("  rays an image pass %.2f M (primary %.2f, shadow %.2f, reflected %.2f, refracted %.2f)\n"
                "  Embree alone traces as many primary rays in %.3f s in 8-wide packets, %.3f s one at a time: the\n"
                "  image pass runs at %.0f%% / %.0f%% of those ray-casting rates\n",
                rays / n / 1e6, r.primary / n / 1e6, r.shadow / n / 1e6, r.reflected / n / 1e6, r.refracted / n / 1e6,
                alone.packets, alone.single, image > 0.0 ? 100.0 * alone.packets / image : 0.0,
                image > 0.0 ? 100.0 * alone.single / image : 0.0);
}

bool progressive_lua_scene(const ProgressiveRecipe& recipe, int threads, TradeScene& scene) {
    const std::string base = progressive_base(recipe);
    const std::string problem = reference_problem(base + ".pfm", base + ".txt", expected_progressive_info(recipe));
    if (!problem.empty()) {
        std::fprintf(stderr,
                     "trade: %s: progressive reference unusable: %s\n  remake it with: build/trade "
                     "--make-references --progressive --scenes %s\n",
                     recipe.name, problem.c_str(), recipe.name);
        return false;
    }
    const ReferenceRecipe& lua = lua_recipe(recipe.name);
    scene.name = recipe.name;
    scene.job = progressive_job(recipe, threads);
    scene.reference = read_pfm(base + ".pfm");
    scene.region = caustic_region(scene.reference);
    scene.reference_kind = reference_dir + "/" + recipe.name + "_progressive.pfm";
    scene.reference_noise = read_reference_info(base + ".txt").noise;
    scene.sweep = lua.sweep;
    scene.quick_sweep = lua.quick_sweep;
    return true;
}

}  // namespace caustica::trade
