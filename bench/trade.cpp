// Speed against accuracy of the caustic photon map (issue 6): sweeps the photon count, the
// neighbour count N and the maximum gather distance on the caustic demo scenes, times the photon
// pass and the render pass of each run, and measures the error against a reference: analytic for
// the virtual-light scene, a stored very-high-photon render (assets/references/) for the others.
// Writes DIR/trade.csv, DIR/presets.csv, DIR/convergence.csv, DIR/pareto.csv and PNG plots (gnuplot).
//   build/trade [--quick] [--repeat K] [--scenes a,b] --out DIR
//   build/trade --make-references          (minutes; never in CI)
// Every run is caustics only (--draw-caustics-only), one sample per pixel, --reproducible, on
// all cores: see docs/ACCURACY.md.
#include "bench/trade_plot.h"
#include "bench/trade_reference.h"
#include "core/lua/scene_loader.h"
#include "core/render/render_session.h"
#include "core/scene/source_location.h"
#include "tests/test_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace caustica;
using caustica::trade::ReferenceInfo;
namespace fs = std::filesystem;

namespace {

const std::string source_dir = CAUSTICA_SOURCE_DIR;
const std::string reference_dir = "assets/references";

/// The default maximum gather distance, 0.15 x unit distance: every scene here has unit distance 1.
constexpr double default_max_dist = 0.15;
/// A pixel belongs to a Lua scene's caustic region when its reference caustic value (mean of the
/// channels) is at least this fraction of the reference's 99th percentile of non-zero values.
constexpr double region_fraction = 0.1;

/// How a stored reference is made: `runs` independent renders (seeds 1..runs) averaged. Each run
/// shoots 30-70x the photons of the largest swept count, so that its gather disc is well inside any
/// swept run's (blur is the error that averaging cannot remove); averaging removes the noise.
struct ReferenceRecipe {
    const char* name;
    const char* script;  ///< relative to the source tree
    int width, height;
    long long photons;   ///< directions per light, per run
    int neighbours;
    int runs;
    std::vector<long long> sweep, quick_sweep;  ///< photon counts of the full and --quick sweeps
};

const std::vector<ReferenceRecipe> recipes = {
    {"default", "scenes/default.lua", 256, 256, 1'000'000'000, 100, 20,
     {10'000, 30'000, 100'000, 300'000, 1'000'000, 3'000'000, 10'000'000, 30'000'000}, {100'000, 300'000, 1'000'000}},
    // The glass covers about 0.45% of the lamp's sphere: its sweep starts a decade higher.
    {"glass_of_liquid", "scenes/glass_of_liquid.lua", 320, 240, 2'000'000'000, 100, 20,
     {100'000, 300'000, 1'000'000, 3'000'000, 10'000'000, 30'000'000}, {300'000, 1'000'000, 3'000'000}},
};

/// Command-line settings.
struct Settings {
    bool quick = false;
    bool make_references = false;
    bool skip_stale = false;
    int repeat = 0;  ///< 0: 1 with --quick, else 3
    std::string out_dir;
    std::vector<std::string> scenes;  ///< empty: all
    int threads = 1;
};

/// A scene of the sweep, ready to render, with its reference and caustic region.
struct TradeScene {
    std::string name;
    RenderJob job;                    ///< harness resolution, caustics only, one sample per pixel
    Image reference;
    std::vector<std::size_t> region;  ///< pixel indices of the caustic region
    std::string reference_kind;       ///< "analytic" or the reference file
    std::vector<long long> sweep, quick_sweep;  ///< photon counts of the full and --quick sweeps
};

/// Error of one image against its scene's reference.
struct ImageError {
    double rmse = 0.0;      ///< over every pixel and channel, of the shown (clamped linear) values
    double rel_rmse = 0.0;  ///< over the caustic region, relative to the reference's mean there
    double rel_bias = 0.0;  ///< sum over the region / reference sum - 1
};

/// One measured run.
struct Row {
    std::string scene;
    long long photons = 0;
    int neighbours = 0;
    double max_dist = 0.0;
    double photon_seconds = 0.0, render_seconds = 0.0;
    ImageError error;
    std::size_t stored_photons = 0;
};

/// Times of one render, split into the photon pass and the image passes.
struct Timing {
    double photon_seconds = 0.0, render_seconds = 0.0;
    std::size_t stored_photons = 0;
};

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The settings every measured run shares: caustics only, one centred sample, fixed streams, all cores.
void set_caustics_only(Options& o, int threads) {
    o.draw_caustics_only = true;
    o.disable_aa = true;
    o.reproducible = true;
    o.seed = 0;
    o.threads = threads;
    o.silent = true;
    o.stats = o.timing = o.verbose = false;
}

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

/// A pixel as the PNG shows it: each channel clamped to [0, 1]. Errors are measured on these
/// values, so a focal spot of radiance 25 counts as much as one of 1, as it looks.
glm::vec3 shown(const glm::vec3& p) { return glm::clamp(p, glm::vec3(0.0f), glm::vec3(1.0f)); }

double pixel_value(const glm::vec3& p) {
    const glm::vec3 s = shown(p);
    return (s.x + s.y + s.z) / 3.0;
}

/// Pixels whose shown reference caustic value reaches region_fraction of the 99th percentile of
/// the non-zero values.
std::vector<std::size_t> caustic_region(const Image& reference) {
    std::vector<double> lit;
    for (const glm::vec3& p : reference.pixels)
        if (pixel_value(p) > 0.0) lit.push_back(pixel_value(p));
    std::vector<std::size_t> region;
    if (lit.empty()) return region;
    auto percentile = lit.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(lit.size() - 1));
    std::nth_element(lit.begin(), percentile, lit.end());
    const double threshold = region_fraction * *percentile;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i)
        if (pixel_value(reference.pixels[i]) >= threshold) region.push_back(i);
    return region;
}

ImageError compare(const Image& image, const Image& reference, const std::vector<std::size_t>& region) {
    ImageError e;
    double squared = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const glm::vec3 d = shown(image.pixels[i]) - shown(reference.pixels[i]);
        squared += glm::dot(d, d);
    }
    e.rmse = std::sqrt(squared / (3.0 * static_cast<double>(image.pixels.size())));
    double region_squared = 0.0, sum = 0.0, sum_reference = 0.0;
    for (std::size_t i : region) {
        const glm::vec3 d = shown(image.pixels[i]) - shown(reference.pixels[i]);
        region_squared += glm::dot(d, d);
        sum += 3.0 * pixel_value(image.pixels[i]);
        sum_reference += 3.0 * pixel_value(reference.pixels[i]);
    }
    if (sum_reference > 0.0) {
        const double count = 3.0 * static_cast<double>(region.size());
        e.rel_rmse = std::sqrt(region_squared / count) / (sum_reference / count);
        e.rel_bias = sum / sum_reference - 1.0;
    }
    return e;
}

RenderJob load_lua_job(const ReferenceRecipe& recipe, int threads) {
    RenderJob job = load_scene_script(source_dir + "/" + recipe.script).renders.at(0);
    job.width = recipe.width;
    job.height = recipe.height;
    job.options.resolution_override = 0;
    set_caustics_only(job.options, threads);
    return job;
}

ReferenceInfo expected_info(const ReferenceRecipe& recipe) {
    ReferenceInfo info;
    info.scene_file = recipe.script;
    info.scene_hash = trade::scene_content_hash(load_lua_job(recipe, 1));
    info.width = recipe.width;
    info.height = recipe.height;
    info.photons = recipe.photons;
    info.neighbours = recipe.neighbours;
    info.max_dist = default_max_dist;
    info.runs = recipe.runs;
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
    info.noise = 0.5 * compare(half_a, half_b, caustic_region(mean)).rel_rmse;
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
    const RenderJob truth_job = truth_builder.build();
    caustica::testing::JobBuilder builder = caustica::testing::virtual_light_scene(false);
    builder.job.width = builder.job.height = 256;
    set_caustics_only(builder.job.options, threads);
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

/// Loads a Lua scene and its stored reference; returns false (with a message) when the reference
/// is missing or stale.
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

Settings parse_arguments(int argc, char** argv) {
    Settings s;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " expects a value");
            return argv[++i];
        };
        if (a == "--quick") s.quick = true;
        else if (a == "--make-references") s.make_references = true;
        else if (a == "--skip-stale") s.skip_stale = true;
        else if (a == "--out") s.out_dir = value();
        else if (a == "--repeat") s.repeat = std::stoi(value());
        else if (a == "--scenes") {
            const std::string list = value();
            for (std::size_t start = 0, comma; start <= list.size(); start = comma + 1) {
                comma = std::min(list.find(',', start), list.size());
                if (comma > start) s.scenes.push_back(list.substr(start, comma - start));
            }
        } else if (a == "--help" || a == "-h") {
            std::printf("usage: trade [--quick] [--repeat K] [--scenes virtual_light,default,glass_of_liquid] "
                        "[--skip-stale] --out DIR\n       trade --make-references [--scenes ...]\n");
            std::exit(0);
        } else throw std::runtime_error("unknown argument '" + a + "' (see --help)");
    }
    for (const std::string& name : s.scenes)
        if (name != "virtual_light" &&
            std::none_of(recipes.begin(), recipes.end(), [&](const ReferenceRecipe& r) { return name == r.name; }))
            throw std::runtime_error("--scenes: unknown scene '" + name + "'");
    if (s.repeat <= 0) s.repeat = s.quick ? 1 : 3;
    if (!s.make_references && s.out_dir.empty()) throw std::runtime_error("--out DIR is required");
    s.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return s;
}

bool wanted(const Settings& s, const std::string& name) {
    return s.scenes.empty() || std::find(s.scenes.begin(), s.scenes.end(), name) != s.scenes.end();
}

/// The sweep of one scene: each photon count is shot once per repetition and every (max distance,
/// N) is gathered from it; times are medians over repetitions (errors do not vary: --reproducible).
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
                        row.error = compare(session.image(), scene.reference, scene.region);
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

/// One preset measured on one scene: caustic error and times, and the full image's render time.
struct PresetRow {
    std::string scene, preset;
    Options options;
    Timing caustics;
    double full_render_seconds = 0.0;
    ImageError error;
};

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
            if (r == 0) row.error = compare(session.image(), scene.reference, scene.region), row.caustics = t;
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

/// Least-squares slope of log10(y) against log10(x).
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

std::string format_count(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

void write_outputs(const Settings& settings, const std::vector<TradeScene>& scenes, const std::vector<Row>& rows,
                   const std::vector<PresetRow>& presets, const std::vector<double>& max_dists,
                   const std::vector<int>& ns) {
    const std::string dir = settings.out_dir;
    std::ofstream csv(dir + "/trade.csv");
    csv << "scene,photons,neighbours,max_dist,photon_seconds,render_seconds,rmse,rel_rmse_caustic,"
           "rel_bias_caustic,stored_photons,reference\n";
    std::map<std::string, std::string> kinds;
    for (const TradeScene& s : scenes) kinds[s.name] = s.reference_kind;
    for (const Row& r : rows) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%lld,%d,%g,%.5f,%.5f,%.6g,%.6g,%.6g,%zu,%s\n", r.scene.c_str(), r.photons,
                      r.neighbours, r.max_dist, r.photon_seconds, r.render_seconds, r.error.rmse, r.error.rel_rmse,
                      r.error.rel_bias, r.stored_photons, kinds[r.scene].c_str());
        csv << line;
    }
    std::ofstream preset_csv(dir + "/presets.csv");
    preset_csv << "scene,preset,photons,neighbours,max_dist,aa_grid,aa_threshold,shadow_grid,photon_seconds,"
                  "caustic_render_seconds,full_render_seconds,rmse,rel_rmse_caustic,rel_bias_caustic\n";
    for (const PresetRow& p : presets) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%lld,%d,%g,%d,%g,%d,%.5f,%.5f,%.5f,%.6g,%.6g,%.6g\n", p.scene.c_str(),
                      p.preset.c_str(), p.options.caustic_num_photons, p.options.caustic_num_neighbours,
                      p.options.effective_caustic_max_dist(), p.options.aa_grid, p.options.aa_threshold,
                      p.options.shadow_grid, p.caustics.photon_seconds, p.caustics.render_seconds,
                      p.full_render_seconds, p.error.rmse, p.error.rel_rmse, p.error.rel_bias);
        preset_csv << line;
    }

    // Convergence: the best N at each photon count, default maximum distance.
    std::ofstream convergence(dir + "/convergence.csv");
    convergence << "scene,photons,best_neighbours,rel_rmse_caustic,rmse\n";
    trade::Panel convergence_panel{"best N at each photon count, max distance " + format_count(default_max_dist),
                                   "photon directions per light", "relative RMSE over the caustic region", {}};
    int colour = 0;
    for (const TradeScene& s : scenes) {
        std::map<long long, const Row*> best;
        for (const Row& r : rows)
            if (r.scene == s.name && std::abs(r.max_dist - default_max_dist) < 1e-12 &&
                (!best.count(r.photons) || r.error.rel_rmse < best[r.photons]->error.rel_rmse))
                best[r.photons] = &r;
        std::vector<std::pair<double, double>> points, rmse_points;
        for (const auto& [photons, r] : best) {
            convergence << s.name << ',' << photons << ',' << r->neighbours << ',' << r->error.rel_rmse << ','
                        << r->error.rmse << '\n';
            points.emplace_back(static_cast<double>(photons), r->error.rel_rmse);
            rmse_points.emplace_back(static_cast<double>(photons), r->error.rmse);
        }
        if (points.size() < 2) continue;
        const double slope = log_log_slope(points), rmse_slope = log_log_slope(rmse_points);
        std::printf("convergence %-16s slope %+.3f (relative RMSE over the caustic region), %+.3f (image RMSE)\n",
                    s.name.c_str(), slope, rmse_slope);
        convergence << "# " << s.name << " slope of log10(rel_rmse_caustic) on log10(photons): " << slope
                    << ", of log10(rmse): " << rmse_slope << '\n';
        // The fitted line through the points' centroid.
        double mx = 0, my = 0;
        for (const auto& [x, y] : points) mx += std::log10(x), my += std::log10(y);
        mx /= static_cast<double>(points.size()), my /= static_cast<double>(points.size());
        auto fitted = [&](double x) { return std::pow(10.0, my + slope * (std::log10(x) - mx)); };
        char title[128];
        std::snprintf(title, sizeof title, "%s (slope %.2f)", s.name.c_str(), slope);
        convergence_panel.curves.push_back({s.name, points, colour});
        convergence_panel.curves.push_back(
            {title, {{points.front().first, fitted(points.front().first)}, {points.back().first, fitted(points.back().first)}},
             colour, true});
        ++colour;
    }

    // The Pareto front of each scene: the runs no other run beats in both time and caustic error.
    std::ofstream pareto(dir + "/pareto.csv");
    pareto << "scene,photons,neighbours,max_dist,seconds,rel_rmse_caustic,rmse\n";
    for (const TradeScene& s : scenes) {
        std::vector<const Row*> runs;
        for (const Row& r : rows)
            if (r.scene == s.name) runs.push_back(&r);
        std::sort(runs.begin(), runs.end(), [](const Row* a, const Row* b) {
            return a->photon_seconds + a->render_seconds < b->photon_seconds + b->render_seconds;
        });
        double best = std::numeric_limits<double>::infinity();
        for (const Row* r : runs)
            if (r->error.rel_rmse < best) {
                best = r->error.rel_rmse;
                pareto << s.name << ',' << r->photons << ',' << r->neighbours << ',' << r->max_dist << ','
                       << r->photon_seconds + r->render_seconds << ',' << r->error.rel_rmse << ',' << r->error.rmse
                       << '\n';
            }
    }

    if (!trade::gnuplot_available()) {
        std::printf("plots skipped: gnuplot is not on PATH (apt-get install gnuplot-nox); the CSV files hold the data\n");
        return;
    }
    std::vector<trade::Figure> figures;
    for (const TradeScene& s : scenes) {
        trade::Figure f;
        f.png_path = dir + "/trade-" + s.name + ".png";
        f.title = s.name + ": caustic error against time (photon pass + render, " + std::to_string(s.job.width) + "x" +
                  std::to_string(s.job.height) + ", " + std::to_string(settings.threads) + " threads), reference: " +
                  s.reference_kind;
        f.rows = 2;
        f.columns = static_cast<int>(max_dists.size());
        f.width = 560 * f.columns;
        f.height = 1000;
        for (int metric = 0; metric < 2; ++metric)
            for (double max_dist : max_dists) {
                trade::Panel panel{"max distance " + format_count(max_dist) +
                                       (std::abs(max_dist - default_max_dist) < 1e-12 ? " (default)" : ""),
                                   "seconds", metric == 0 ? "relative RMSE over the caustic region" : "image RMSE", {}};
                for (std::size_t k = 0; k < ns.size(); ++k) {
                    trade::Curve curve{"N = " + std::to_string(ns[k]), {}, static_cast<int>(k)};
                    for (const Row& r : rows)
                        if (r.scene == s.name && r.neighbours == ns[k] && std::abs(r.max_dist - max_dist) < 1e-12)
                            curve.points.emplace_back(r.photon_seconds + r.render_seconds,
                                                      metric == 0 ? r.error.rel_rmse : r.error.rmse);
                    panel.curves.push_back(curve);
                }
                f.panels.push_back(panel);
            }
        figures.push_back(f);
    }
    trade::Figure convergence_figure;
    convergence_figure.png_path = dir + "/convergence.png";
    convergence_figure.title = "Convergence of the caustic estimate (dashed: least-squares fit)";
    convergence_figure.width = 900;
    convergence_figure.height = 650;
    convergence_figure.panels.push_back(convergence_panel);
    figures.push_back(convergence_figure);
    for (const trade::Figure& f : figures) {
        const std::string problem = trade::plot_figure(f);
        if (problem.empty()) std::printf("wrote %s\n", f.png_path.c_str());
        else std::printf("plot not drawn: %s\n", problem.c_str());
    }
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Settings settings = parse_arguments(argc, argv);
        if (settings.make_references) {
            for (const ReferenceRecipe& recipe : recipes)
                if (wanted(settings, recipe.name)) make_reference(recipe, settings.threads);
            return 0;
        }
        fs::create_directories(settings.out_dir);
        std::printf("trade: %s sweep, %d threads, --reproducible, caustics only, one sample per pixel\n",
                    settings.quick ? "quick" : "full", settings.threads);
        std::vector<TradeScene> scenes;
        bool unusable = false;
        if (wanted(settings, "virtual_light")) scenes.push_back(virtual_light(settings.threads));
        for (const ReferenceRecipe& recipe : recipes) {
            if (!wanted(settings, recipe.name)) continue;
            TradeScene scene;
            if (lua_scene(recipe, settings.threads, scene)) scenes.push_back(std::move(scene));
            else unusable = true;
        }
        if (unusable && !settings.skip_stale) {
            std::fprintf(stderr, "trade: stopping (--skip-stale measures the other scenes)\n");
            return 3;
        }
        for (const TradeScene& s : scenes)
            std::printf("%s: reference %s, caustic region %zu of %d pixels\n", s.name.c_str(), s.reference_kind.c_str(),
                        s.region.size(), s.job.width * s.job.height);

        const std::vector<int> ns = settings.quick ? std::vector<int>{25, 100} : std::vector<int>{10, 25, 50, 100, 200, 500};
        const std::vector<double> max_dists = {0.5 * default_max_dist, default_max_dist, 2.0 * default_max_dist};
        std::vector<Row> rows;
        std::vector<PresetRow> presets;
        for (const TradeScene& s : scenes) {
            const std::vector<Row> scene_rows = sweep(s, settings.quick ? s.quick_sweep : s.sweep, ns, max_dists, settings.repeat);
            rows.insert(rows.end(), scene_rows.begin(), scene_rows.end());
            const std::vector<PresetRow> scene_presets = measure_presets(s, settings.repeat);
            presets.insert(presets.end(), scene_presets.begin(), scene_presets.end());
        }
        write_outputs(settings, scenes, rows, presets, max_dists, ns);
        std::printf("wrote %s/trade.csv\n", settings.out_dir.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "trade: %s\n", e.what());
        return 2;
    }
}
