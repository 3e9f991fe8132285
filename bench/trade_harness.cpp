// The trade harness's scenes, references, sweep and presets (see trade_harness.h).
#include "bench/trade_harness.h"

#include "bench/trade_reference.h"
#include "core/lua/scene_loader.h"
#include "core/render/render_session.h"
#include "tests/test_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustica::trade {

namespace fs = std::filesystem;

const std::vector<ReferenceRecipe> recipes = {
    {"default", "scenes/default.lua", 256, 256, 1'000'000'000, 100, 20,
     {10'000, 30'000, 100'000, 300'000, 1'000'000, 3'000'000, 10'000'000, 30'000'000}, {100'000, 300'000, 1'000'000}},
    // The glass covers about 0.45% of the lamp's sphere: its sweep starts a decade higher.
    {"glass_of_liquid", "scenes/glass_of_liquid.lua", 320, 240, 2'000'000'000, 100, 20,
     {100'000, 300'000, 1'000'000, 3'000'000, 10'000'000, 30'000'000}, {300'000, 1'000'000, 3'000'000}},
};

namespace {

const std::string source_dir = CAUSTICA_SOURCE_DIR;
const std::string reference_dir = "assets/references";

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

void set_caustics_only(Options& o, int threads) {
    o.integrator = IntegratorKind::progressive;
    o.draw_caustics_only = true;
    o.disable_aa = true;
    o.reproducible = true;
    o.seed = 0;
    o.threads = threads;
    o.silent = true;
    o.stats = o.timing = o.verbose = false;
}

namespace {

Timing render(RenderSession& session, const RenderJob& job) {
    session.set_job(job);
    session.start();
    if (!session.wait()) throw std::runtime_error("render cancelled");
    Timing t;
    const RenderStats stats = session.stats();
    for (const StageTime& s : stats.stages) {
        if (s.name == "projection maps" || s.name == "photon shooting" || s.name == "photon k-d tree")
            t.photon_seconds += s.seconds;
        if (s.name == "first samples" || s.name == "anti-aliasing") t.render_seconds += s.seconds;
    }
    t.stored_photons = stats.caustic_photons;
    return t;
}

}  // namespace

RenderJob load_lua_job(const ReferenceRecipe& recipe, int threads) {
    RenderJob job = load_scene_script(source_dir + "/" + recipe.script).renders.at(0);
    job.width = recipe.width;
    job.height = recipe.height;
    job.options.resolution_override = 0;
    set_caustics_only(job.options, threads);
    job.miss_colour = glm::dvec3(0.0);  // caustics only: rays that leave the scene add nothing
    return job;
}

namespace {

ReferenceInfo expected_info(const ReferenceRecipe& recipe) {
    return recipe_info(recipe.script, load_lua_job(recipe, 1), recipe.photons, recipe.neighbours, default_max_dist,
                       recipe.runs);
}

}  // namespace

ReferenceInfo recipe_info(const std::string& script, const RenderJob& job, long long photons, int neighbours,
                          double max_dist, int runs) {
    ReferenceInfo info;
    info.scene_file = script;
    info.scene_hash = trade::scene_content_hash(job);
    info.width = job.width;
    info.height = job.height;
    info.photons = photons;
    info.neighbours = neighbours;
    info.max_dist = max_dist;
    info.runs = runs;
    return info;
}

/// Renders the reference of one Lua scene: the mean of `runs` renders with seeds 1..runs.
void make_reference(const ReferenceRecipe& recipe, int threads) {
    const double t0 = now_seconds();
    RenderJob job = load_lua_job(recipe, threads);
    job.options.caustic_num_photons = recipe.photons;
    job.options.caustic_num_neighbours = recipe.neighbours;
    job.options.caustic_max_dist = default_max_dist;
    Image sum(job.width, job.height), first_half(job.width, job.height);
    for (int run = 1; run <= recipe.runs; ++run) {
        job.options.seed = run;
        RenderSession session;
        const Timing t = render(session, job);
        for (std::size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += session.image().pixels[i];
        if (run == recipe.runs / 2) first_half = sum;
        std::printf("  %s: run %d/%d, %zu photons stored, photon pass %.1f s, render %.1f s\n", recipe.name, run,
                    recipe.runs, t.stored_photons, t.photon_seconds, t.render_seconds);
        std::fflush(stdout);
    }
    Image mean = sum, half_a = first_half, half_b(sum.width, sum.height);
    const int half = recipe.runs / 2;
    for (std::size_t i = 0; i < sum.pixels.size(); ++i) {
        mean.pixels[i] /= static_cast<float>(recipe.runs);
        half_a.pixels[i] /= static_cast<float>(half);
        half_b.pixels[i] = (sum.pixels[i] - first_half.pixels[i]) / static_cast<float>(recipe.runs - half);
    }
    ReferenceInfo info = expected_info(recipe);
    // The two halves' difference has 4x the variance of the full mean's error: halve its RMSE.
    info.noise = 0.5 * compare_images(half_a, half_b, caustic_region(mean)).rel_rmse;
    info.seconds = now_seconds() - t0;
    info.command = "build/trade --make-references";
    const std::string base = source_dir + "/" + reference_dir + "/" + recipe.name;
    fs::create_directories(source_dir + "/" + reference_dir);
    trade::write_pfm(base + ".pfm", mean);
    trade::write_reference_info(base + ".txt", info);
    std::printf("  %s: wrote %s.pfm in %.0f s (own noise %.4f relative RMSE over the caustic region)\n", recipe.name,
                base.c_str(), info.seconds, info.noise);
}

TradeScene virtual_light(int threads) {
    caustica::testing::JobBuilder truth_builder = caustica::testing::virtual_light_scene(true);
    truth_builder.job.width = truth_builder.job.height = 256;
    truth_builder.job.options.threads = threads;
    truth_builder.job.options.integrator = IntegratorKind::progressive;  // the analytic virtual light's physics
    truth_builder.job.miss_colour = glm::dvec3(0.0);  // as the caustics-only job below
    const RenderJob truth_job = truth_builder.build();
    caustica::testing::JobBuilder builder = caustica::testing::virtual_light_scene(false);
    builder.job.width = builder.job.height = 256;
    set_caustics_only(builder.job.options, threads);
    builder.job.miss_colour = glm::dvec3(0.0);  // caustics only: rays that leave the scene add nothing
    TradeScene scene;
    scene.name = "virtual_light";
    scene.job = builder.build();
    scene.reference = caustica::testing::render(truth_job);
    scene.region = caustica::testing::virtual_light_annulus(truth_job);
    scene.reference_kind = "analytic";
    scene.sweep = {10'000, 30'000, 100'000, 300'000, 1'000'000, 3'000'000, 10'000'000};
    scene.quick_sweep = {10'000, 100'000, 300'000};
    return scene;
}

bool lua_scene(const ReferenceRecipe& recipe, int threads, TradeScene& scene) {
    const std::string base = source_dir + "/" + reference_dir + "/" + recipe.name;
    const std::string problem = trade::reference_problem(base + ".pfm", base + ".txt", expected_info(recipe));
    if (!problem.empty()) {
        std::fprintf(stderr, "trade: %s: reference unusable: %s\n  remake it with: build/trade --make-references\n",
                     recipe.name, problem.c_str());
        return false;
    }
    scene.name = recipe.name;
    scene.job = load_lua_job(recipe, threads);
    scene.reference = trade::read_pfm(base + ".pfm");
    scene.region = caustic_region(scene.reference);
    scene.reference_kind = reference_dir + "/" + recipe.name + ".pfm";
    scene.sweep = recipe.sweep;
    scene.quick_sweep = recipe.quick_sweep;
    return true;
}

std::vector<Row> sweep(const TradeScene& scene, const std::vector<long long>& counts, const std::vector<int>& ns,
                       const std::vector<double>& max_dists, int repeat) {
    std::vector<Row> rows;
    for (long long photons : counts) {
        std::vector<double> photon_times;
        std::map<std::pair<double, int>, std::vector<double>> render_times;
        std::map<std::pair<double, int>, Row> measured;
        for (int r = 0; r < repeat; ++r) {
            RenderSession session;
            for (double max_dist : max_dists)
                for (int n : ns) {
                    RenderJob job = scene.job;
                    job.options.caustic_num_photons = photons;
                    job.options.caustic_num_neighbours = n;
                    job.options.caustic_max_dist = max_dist;
                    const Timing t = render(session, job);
                    if (photon_times.size() == static_cast<std::size_t>(r)) photon_times.push_back(t.photon_seconds);
                    render_times[{max_dist, n}].push_back(t.render_seconds);
                    if (r == 0) {
                        Row row{scene.name, photons, n, max_dist, 0.0, 0.0, {}, t.stored_photons};
                        row.error = compare_images(session.image(), scene.reference, scene.region);
                        measured[{max_dist, n}] = row;
                    }
                }
        }
        for (auto& [key, row] : measured) {
            row.photon_seconds = median(photon_times);
            row.render_seconds = median(render_times[key]);
            std::printf("%-16s %10lld  N %3d  max %.3f  photon %7.3f s  render %6.3f s  rel %.4f  rmse %.5f\n",
                        row.scene.c_str(), row.photons, row.neighbours, row.max_dist, row.photon_seconds,
                        row.render_seconds, row.error.rel_rmse, row.error.rmse);
            rows.push_back(row);
        }
        std::fflush(stdout);
    }
    return rows;
}

std::vector<PresetRow> measure_presets(const TradeScene& scene, int repeat) {
    std::vector<PresetRow> rows;
    for (const char* preset : {"draft", "preview", "final"}) {
        PresetRow row{scene.name, preset, scene.job.options, {}, 0.0, {}};
        apply_option_tokens(row.options, {"--quality", preset});
        std::vector<double> photon_times, caustic_times, full_times;
        for (int r = 0; r < repeat; ++r) {
            RenderSession session;
            RenderJob job = scene.job;
            job.options = row.options;
            const Timing t = render(session, job);
            if (r == 0) row.error = compare_images(session.image(), scene.reference, scene.region), row.caustics = t;
            photon_times.push_back(t.photon_seconds);
            caustic_times.push_back(t.render_seconds);
            job.options.draw_caustics_only = false;  // the whole image, anti-aliased as the preset says
            job.options.disable_aa = false;
            full_times.push_back(render(session, job).render_seconds);
        }
        row.caustics.photon_seconds = median(photon_times);
        row.caustics.render_seconds = median(caustic_times);
        row.full_render_seconds = median(full_times);
        std::printf("%-16s preset %-8s photon %7.3f s  caustic render %6.3f s  full render %6.3f s  rel %.4f\n",
                    scene.name.c_str(), preset, row.caustics.photon_seconds, row.caustics.render_seconds,
                    row.full_render_seconds, row.error.rel_rmse);
        rows.push_back(row);
    }
    return rows;
}

}  // namespace caustica::trade
