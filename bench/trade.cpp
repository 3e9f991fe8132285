// Speed against accuracy of the caustic photon map (docs/ACCURACY.md): sweeps the photon count, the
// neighbour count N and the maximum gather distance on the caustic demo scenes, times the photon
// pass and the render pass of each run, and measures the error against a reference: analytic for
// the virtual-light scene, a stored very-high-photon render (assets/references/) for the others.
// Writes DIR/trade.csv, DIR/presets.csv, DIR/convergence.csv, DIR/pareto.csv and PNG plots (gnuplot).
//   build/trade [--quick] [--repeat K] [--scenes a,b] --out DIR
//   build/trade --make-references          (minutes; never in CI)
// Every run is caustics only (--draw-caustics-only), one sample per pixel, --reproducible, on
// all cores: see docs/ACCURACY.md.
#include "bench/trade_harness.h"
#include "bench/trade_plot.h"
#include "bench/trade_progressive.h"
#include "bench/trade_reference.h"
#include "core/io/png_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace caustica;
using namespace caustica::trade;
namespace fs = std::filesystem;

namespace {

/// Command-line settings.
struct Settings {
    bool quick = false;
    bool make_references = false;
    bool skip_stale = false;
    bool progressive = false;          ///< error-against-time curves of accumulating renders
    bool pass_time = false;            ///< the time of a progressive pass of the default scene at 1280 x 720
    bool progressive_references = false;  ///< against the pixel-averaged references (else the stored ones)
    bool classic = false;              ///< with --progressive: the single k-nearest pass beside it
    std::vector<std::pair<std::string, ProgressiveRun>> tuned;  ///< --tuned SCENE:N:PHOTONS:MAXDIST, more curves
    ProgressiveRun run;
    int repeat = 0;  ///< 0: 1 with --quick, else 3
    std::string out_dir;
    std::vector<std::string> scenes;  ///< empty: all
    int threads = 1;
};

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
        else if (a == "--progressive") s.progressive = true;
        else if (a == "--pass-time") s.pass_time = true;
        else if (a == "--averaged-references") s.progressive_references = true;
        else if (a == "--classic") s.classic = true;
        else if (a == "--tuned") {
            // SCENE:RADIUS:PHOTONS:MAXDIST, e.g. default:2:1e7:0.15 (the passes and seconds as given)
            std::string text = value();
            std::vector<std::string> parts;
            for (std::size_t start = 0, colon; start <= text.size(); start = colon + 1) {
                colon = std::min(text.find(':', start), text.size());
                parts.push_back(text.substr(start, colon - start));
            }
            if (parts.size() != 4) throw std::runtime_error("--tuned expects SCENE:RADIUS:PHOTONS:MAXDIST");
            ProgressiveRun run;
            run.radius = std::stod(parts[1]);
            run.photons = static_cast<long long>(std::stod(parts[2]));
            run.max_dist = std::stod(parts[3]);
            s.tuned.emplace_back(parts[0], run);
        }
        else if (a == "--passes") s.run.max_passes = std::stoi(value());
        else if (a == "--seconds") s.run.max_seconds = std::stod(value());
        else if (a == "--photons") s.run.photons = static_cast<long long>(std::stod(value()));
        else if (a == "--radius") s.run.radius = std::stod(value());
        else if (a == "--max-dist") s.run.max_dist = std::stod(value());
        else if (a == "--photon-split") s.run.split = true;
        else if (a == "--adaptive-radius") s.run.adaptive_radius = true;
        else if (a == "--auto-radius") s.run.auto_radius = true;
        else if (a == "--guided-emission") {
            const std::string v = value();
            if (v != "on" && v != "off") throw std::runtime_error("--guided-emission expects on or off, not '" + v + "'");
            s.run.guided_emission = v == "on" ? 1 : 0;
        }
        else if (a == "--photons-per-pixel") s.run.photons_per_pixel = std::stod(value());
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
                        "[--skip-stale] --out DIR\n       trade --make-references [--progressive] [--scenes ...]\n"
                        "       trade --progressive [--averaged-references] [--classic] [--tuned SCENE:RADIUS:PHOTONS:MAXDIST]... [--passes P] [--seconds S] "
                        "[--photons X] [--radius PIXELS] [--max-dist D] [--photon-split] [--adaptive-radius] [--auto-radius] [--guided-emission on|off] [--photons-per-pixel K] [--scenes ...] --out DIR\n"
                        "       trade --pass-time [--passes P]   (a progressive pass of default.lua at 1280x720)\n");
            std::exit(0);
        } else throw std::runtime_error("unknown argument '" + a + "' (see --help)");
    }
    for (const std::string& name : s.scenes)
        if (name != "virtual_light" &&
            std::none_of(recipes.begin(), recipes.end(), [&](const ReferenceRecipe& r) { return name == r.name; }))
            throw std::runtime_error("--scenes: unknown scene '" + name + "'");
    if (s.repeat <= 0) s.repeat = s.quick ? 1 : 3;
    if (!s.make_references && !s.pass_time && s.out_dir.empty()) throw std::runtime_error("--out DIR is required");
    s.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return s;
}

bool wanted(const Settings& s, const std::string& name) {
    return s.scenes.empty() || std::find(s.scenes.begin(), s.scenes.end(), name) != s.scenes.end();
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

/// Error against time of accumulating renders (--progressive): one accumulation per scene,
/// checkpointed at 1, 2, 4, ... passes; writes DIR/progressive.csv and DIR/progressive.png.
int run_progressive(const Settings& settings) {
    std::vector<TradeScene> scenes;
    bool unusable = false;
    if (wanted(settings, "virtual_light")) {
        TradeScene scene = virtual_light(settings.threads);
        // A jittered accumulation converges to the pixel-averaged image, not the pixel centres' (the
        // blocker's shadow edge crosses the annulus); 1024 jittered passes of direct light, a few seconds.
        const Image centres = scene.reference;
        scene.reference = pixel_averaged_virtual_light(scene, 1024, settings.threads);
        scene.reference_kind = "analytic (pixel-averaged)";
        trade::write_pfm(settings.out_dir + "/virtual_light_centres.pfm", centres);
        trade::write_pfm(settings.out_dir + "/virtual_light_averaged.pfm", scene.reference);
        std::printf("virtual_light: pixel-averaged against pixel-centre analytic reference: %.5f relative RMSE\n",
                    compare_images(scene.reference, centres, scene.region).rel_rmse);
        scenes.push_back(std::move(scene));
    }
    for (const ReferenceRecipe& recipe : recipes) {
        if (!wanted(settings, recipe.name)) continue;
        TradeScene scene;
        bool usable = false;
        if (settings.progressive_references) {
            for (const ProgressiveRecipe& p : progressive_recipes)
                if (std::string(p.name) == recipe.name) usable = progressive_lua_scene(p, settings.threads, scene);
        } else {
            usable = lua_scene(recipe, settings.threads, scene);
        }
        if (usable) scenes.push_back(std::move(scene));
        else unusable = true;
    }
    if (unusable && !settings.skip_stale) {
        std::fprintf(stderr, "trade: stopping (--skip-stale measures the other scenes)\n");
        return 3;
    }
    std::ofstream csv(settings.out_dir + "/progressive.csv");
    csv << "scene,width,height,photons_per_pass,radius_pixels,max_dist,passes,seconds,rel_rmse_caustic,rel_bias_caustic,"
           "rmse,estimate,estimate_noise,estimate_bias,first_radius,radius,photons_emitted,reference,"
           "rel_rmse_less_reference_noise\n";
    std::vector<trade::Panel> panels;
    for (const TradeScene& s : scenes) {
        panels.push_back({s.name + " (" + std::to_string(s.job.width) + "x" + std::to_string(s.job.height) + ", " +
                              (s.name == "virtual_light" ? "analytic" : "pixel-averaged") + " reference)",
                          "seconds", "relative RMSE over the caustic region", {}});
        trade::Panel& errors = panels.back();
        write_png_atomic(settings.out_dir + "/reference-" + s.name + ".png", s.reference, PixelEncoding::clamped_linear);
        // One accumulation: a row per checkpoint, a curve (and for the first, the estimate's curve).
        auto measure = [&](const ProgressiveRun& given, int colour) {
            const Options& o = s.job.options;
            ProgressiveRun run = given;
            run.max_passes = settings.run.max_passes;  // every curve stops by the same rules
            run.max_seconds = settings.run.max_seconds;
            run.split = settings.run.split;
            if (run.photons <= 0 && o.caustic_num_photons <= 0) run.photons = 100'000;  // the virtual light has none
            run.png_path = settings.out_dir + "/progressive-" + s.name + (colour > 0 ? "-" + std::to_string(colour) : "") + ".png";
            const long long photons = run.photons > 0 ? run.photons : o.caustic_num_photons;
            const double radius = run.radius > 0.0 ? run.radius : o.accumulation_radius;
            const double max_dist = run.max_dist > 0.0 ? run.max_dist : o.effective_caustic_max_dist();
            std::printf("%s: %dx%d, %lld photons a pass, first radius %g pixels, max distance %g, reference %s, caustic region %zu pixels\n",
                        s.name.c_str(), s.job.width, s.job.height, photons, radius, max_dist, s.reference_kind.c_str(),
                        s.region.size());
            const std::vector<ProgressivePoint> points = progressive_curve(s, run);
            std::vector<std::pair<double, double>> truth, estimate, fit;
            for (const ProgressivePoint& p : points) {
                char line[512];
                std::snprintf(line, sizeof line, "%s,%d,%d,%lld,%g,%g,%d,%.5f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%lld,%s,%.6g\n",
                              s.name.c_str(), s.job.width, s.job.height, photons, radius, max_dist, p.passes, p.seconds,
                              p.error.rel_rmse, p.error.rel_bias, p.error.rmse, p.estimate, p.noise, p.bias, p.first_radius,
                              p.radius, p.photons_emitted, s.reference_kind.c_str(), p.rel_rmse_less_noise);
                csv << line;
                truth.emplace_back(p.seconds, p.error.rel_rmse);
                if (p.estimate > 0.0) estimate.emplace_back(p.seconds, p.estimate);
                // The slope is fitted over the last two decades of time (all points when shorter).
                if (p.seconds >= points.back().seconds / 100.0) fit.emplace_back(p.seconds, p.error.rel_rmse);
            }
            const double slope = log_log_slope(fit);
            // The estimate against the measured error, and against it less the reference's own noise
            // (from pass 4 on, where the estimate is asked to hold).
            double ratio_min = 1e30, ratio_max = 0.0, less_min = 1e30, less_max = 0.0;
            auto widen = [](double& lo, double& hi, double estimate, double truth) {
                if (!(truth > 0.0)) return;
                lo = std::min(lo, estimate / truth);
                hi = std::max(hi, estimate / truth);
            };
            for (const ProgressivePoint& p : points) {
                if (p.passes < 4 || !(p.estimate > 0.0)) continue;
                widen(ratio_min, ratio_max, p.estimate, p.error.rel_rmse);
                widen(less_min, less_max, p.estimate, p.rel_rmse_less_noise);
            }
            std::printf("progressive %-16s slope %+.3f in time over %.2f decades (%.3f .. %.3f s); estimate / true %.2f .. %.2f "
                        "from 4 passes (%.2f .. %.2f with the reference's noise %.4f taken out)\n",
                        s.name.c_str(), slope, std::log10(fit.back().first / fit.front().first), fit.front().first,
                        fit.back().first, ratio_min, ratio_max, less_min, less_max, s.reference_noise);
            csv << "# " << s.name << " slope of log10(rel_rmse_caustic) on log10(seconds) over the last two decades: "
                << slope << "\n";
            errors.curves.push_back({"progressive, " + format_count(static_cast<double>(photons)) + " photons a pass, r1 " +
                                         format_count(radius) + " px" +
                                         (max_dist != default_max_dist ? ", max " + format_count(max_dist) : "") +
                                         " (slope " + format_count(std::round(slope * 100.0) / 100.0) + ")",
                                     truth, colour});
            if (colour == 0) errors.curves.push_back({"the renderer's estimate", estimate, 0, true});
        };
        measure(settings.run, 0);
        int colour = 4;
        for (const auto& [scene_name, run] : settings.tuned)
            if (scene_name == s.name) measure(run, colour++);
        if (settings.classic && s.name != "virtual_light") {
            // The single k-nearest pass on the same reference: pixel-averaged as well, by 3 x 3
            // anti-aliasing of every pixel (threshold 0), at the photon counts of the sweep.
            TradeScene classic = s;
            classic.job.options.disable_aa = false;
            classic.job.options.aa_grid = 3;
            classic.job.options.aa_threshold = 0.0;
            const std::vector<long long> counts = {1'000'000, 3'000'000, 10'000'000, 30'000'000, 100'000'000};
            const std::vector<Row> rows = sweep(classic, counts, {8, 25}, {default_max_dist}, 1);
            for (int neighbours : {8, 25}) {
                trade::Curve curve{"one k-nearest pass, 3x3 AA, N " + std::to_string(neighbours), {},
                                   neighbours == 8 ? 1 : 3};
                for (const Row& r : rows)
                    if (r.neighbours == neighbours) {
                        curve.points.emplace_back(r.photon_seconds + r.render_seconds, r.error.rel_rmse);
                        char line[256];
                        std::snprintf(line, sizeof line, "%s,%d,%d,%lld,%d,%g,classic,%.5f,%.6g,%.6g,%.6g,,,,,,%lld,%s\n",
                                      s.name.c_str(), s.job.width, s.job.height, r.photons, r.neighbours, r.max_dist,
                                      r.photon_seconds + r.render_seconds, r.error.rel_rmse, r.error.rel_bias,
                                      r.error.rmse, r.photons, s.reference_kind.c_str());
                        csv << line;
                    }
                errors.curves.push_back(curve);
            }
        }
    }
    csv.close();
    std::printf("wrote %s/progressive.csv\n", settings.out_dir.c_str());
    if (!trade::gnuplot_available()) return 0;
    trade::Figure figure;
    figure.png_path = settings.out_dir + "/progressive.png";
    figure.title = "Progressive photon mapping: caustic error against time (" + std::to_string(settings.threads) +
                   " threads)";
    figure.columns = static_cast<int>(panels.size());
    figure.width = 620 * figure.columns;
    figure.height = 620;
    figure.panels = panels;
    const std::string problem = trade::plot_figure(figure);
    if (problem.empty()) std::printf("wrote %s\n", figure.png_path.c_str());
    else std::printf("plot not drawn: %s\n", problem.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Settings settings = parse_arguments(argc, argv);
        if (settings.pass_time) {
            pass_timing("default", 1280, 720, settings.run.max_passes, settings.threads);
            return 0;
        }
        if (settings.make_references && settings.progressive) {
            for (const ProgressiveRecipe& recipe : progressive_recipes)
                if (wanted(settings, recipe.name)) make_progressive_reference(recipe, settings.threads);
            return 0;
        }
        if (settings.make_references) {
            for (const ReferenceRecipe& recipe : recipes)
                if (wanted(settings, recipe.name)) make_reference(recipe, settings.threads);
            return 0;
        }
        fs::create_directories(settings.out_dir);
        if (settings.progressive) return run_progressive(settings);
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
        if (settings.quick && !scenes.empty() && scenes.front().name == "virtual_light") {
            // A tiny progressive check (about 0.3 s): 8 accumulated passes must beat one.
            ProgressiveRun run;
            run.photons = 100'000;
            run.max_passes = 8;
            TradeScene scene = scenes.front();
            scene.reference = pixel_averaged_virtual_light(scene, 16, settings.threads);
            const std::vector<ProgressivePoint> points = progressive_curve(scene, run);
            if (!(points.back().error.rel_rmse < 0.7 * points.front().error.rel_rmse)) {
                std::fprintf(stderr, "trade: progressive passes do not converge on the virtual light (%.4f -> %.4f)\n",
                             points.front().error.rel_rmse, points.back().error.rel_rmse);
                return 4;
            }
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "trade: %s\n", e.what());
        return 2;
    }
}
