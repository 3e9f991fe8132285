#include "core/integrators/progressive_render.h"

#include "core/geometry/render_scene.h"
#include "core/integrators/progressive.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/guided_emission.h"
#include "core/scene/camera.h"
#include "core/render/random.h"
#include "core/render/render_session.h"
#include "core/util/cancel_flag.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace caustica {
namespace {

/// The grid's cells, in typical radii: a gather of that radius scans about (1 + 2/3)^3 = 4.6 cells
/// (2 radii: 8 cells, each holding fewer photons, and slower gathers: docs/PERFORMANCE.md,
/// "Progressive photon mapping").
constexpr double grid_cell_factor = 3.0;

/// The first of first, first * ratio, first * ratio^2, ... after `pass`, or 0 past the sums' capacity.
int next_update_after(int pass, long long first, int ratio) {
    long long next = first;
    while (next <= pass) next *= ratio;
    return next < max_accumulated_passes ? static_cast<int>(next) : 0;
}

/// The first pass after `pass` before which the pixels' radii are adapted (docs/CAUSTICS.md, "A
/// radius per pixel"): 8, 32, 128, ... (the first after two passes in each replicate group, so
/// that each pixel's noise and blur have been measured), or 0 past the sums' capacity.
int adaptation_after(int pass) { return next_update_after(pass, 2 * replicate_groups, 4); }

/// The first pass after `pass` before which --auto-radius scales the radii: 4, 8, 16, ... (from
/// pass 4 every replicate group has a pass, and the estimate its noise from their spread).
int balance_after(int pass) { return next_update_after(pass, replicate_groups, 2); }

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The first gather radius most pixels will use: --accumulation-radius pixel footprints at the
/// median distance pixel-centre rays of a 16 x 16 grid travel to the scene, at most the maximum
/// distance (the grid's cell size before any gather has told). Meaningless once setup.cancel is set.
double typical_first_radius(const RenderScene& scene, const Camera& camera, const RenderJob& job,
                            const ShadingSetup& setup) {
    std::vector<float> distances;
    constexpr int samples = 16;
    for (int j = 0; j < samples; ++j)
        for (int i = 0; i < samples; ++i) {
            SurfaceHit hit;
            const Ray ray = camera.generate((i + 0.5f) * static_cast<float>(job.width) / samples,
                                            (j + 0.5f) * static_cast<float>(job.height) / samples);
            if (scene.intersect(ray, hit, setup.cancel)) distances.push_back(hit.t);
        }
    const double max_distance = static_cast<float>(job.options.effective_caustic_max_dist());
    if (distances.empty()) return max_distance;
    std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2), distances.end());
    const double median = distances[distances.size() / 2];
    return std::min(max_distance,
                    job.options.accumulation_radius * setup.dot_radius_per_distance * median);
}

/// Debug builds check every pixel: a NaN or infinity is a bug to find, not a value to clamp.
inline void check_pixel([[maybe_unused]] const glm::vec3& c, [[maybe_unused]] int x, [[maybe_unused]] int y) {
#ifndef NDEBUG
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
        throw std::logic_error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
#endif
}

/// Writes the accumulated means into every tile of `image` and publishes them.
void publish_means(RenderHost& host, const ProgressiveAccumulator& accumulator, Image& image) {
    host.publish_tiles([&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x)
                image.at(x, y) = accumulator.mean(static_cast<std::size_t>(y) * image.width + x);
    });
}

}  // namespace

void render_accumulation_tile(const ProgressiveIntegrator& integrator, const TileContext& context, const Tile& tile,
                              int pass, const float* radius_factors, ProgressiveAccumulator& accumulator, Image& out,
                              RayCounters& counters, const std::vector<AccumulatedLayer>* layers) {
    // The probes are read from zero around each ray (then added back), so that what a pixel gets
    // does not depend on what else the thread's counters summed: the same bits for any thread count.
    const double photon_before = counters.photon_value, inner_before = counters.photon_value_inner;
    double photon_total = 0.0, inner_total = 0.0;
    // The sample's place in the pixel: pass after pass of a replicate group, a step of the R2
    // sequence from a start fixed per pixel and group, so a pixel's samples cover it evenly
    // whatever the number of passes, and the groups stay independent of each other.
    const double step_x = 0.7548776662466927, step_y = 0.5698402909980532;
    const int group = pass % replicate_groups;
    const double step = static_cast<double>(pass / replicate_groups);
    bool cut_short = false;  // by a cancel: the packet traced then adds nothing
    for (int y = tile.y0; y < tile.y1 && !cut_short; ++y) {
        for (int x = tile.x0; x < tile.x1; x += 8) {
            Ray rays[8];
            int valid[8];
            float scales[8];
            RandomStream streams[8] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}};
            for (int i = 0; i < 8; ++i) {
                valid[i] = x + i < tile.x1;
                const std::size_t index = static_cast<std::size_t>(y) * out.width + x + i;
                scales[i] = radius_factors && valid[i] ? std::sqrt(radius_factors[index]) : 1.0f;
                RandomStream start(context.seed, index, 12 + static_cast<std::uint64_t>(group));
                double jx = start.uniform() + step_x * step, jy = start.uniform() + step_y * step;
                jx -= std::floor(jx);
                jy -= std::floor(jy);
                rays[i] = context.camera->generate(static_cast<float>(x + i) + static_cast<float>(jx),
                                                   static_cast<float>(y) + static_cast<float>(jy));
                // One stream per (pixel, pass): the same image for any thread count.
                streams[i] = RandomStream(context.seed, index, 16 + static_cast<std::uint64_t>(pass));
            }
            // The layers trace with the streams the image's samples start from.
            const std::size_t layer_count = layers ? layers->size() : 0;
            RandomStream initial[8] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}};
            if (layer_count > 0) std::copy(std::begin(streams), std::end(streams), std::begin(initial));
            glm::vec3 colour[8];
            double photon[8], inner[8];
            integrator.trace_samples8(rays, valid, streams, radius_factors ? scales : nullptr, colour, photon, inner,
                                      counters);
            cut_short = is_cancelled(context.cancel);
            if (cut_short) break;
            // Each layer's samples, all traced before any is added: a cancel adds nothing of the packet.
            glm::vec3 layer_colour[std::size(written_layers)][8];
            for (std::size_t l = 0; l < layer_count; ++l) {
                RandomStream same[8] = {initial[0], initial[1], initial[2], initial[3],
                                        initial[4], initial[5], initial[6], initial[7]};
                double unused[8], unused_inner[8];
                RayCounters layer_counters;  // the layers' rays are not the render's
                (*layers)[l].integrator->trace_samples8(rays, valid, same, radius_factors ? scales : nullptr,
                                                        layer_colour[l], unused, unused_inner, layer_counters);
            }
            cut_short = layer_count > 0 && is_cancelled(context.cancel);
            if (cut_short) break;
            for (int i = 0; i < 8 && valid[i]; ++i) {
                PassSample sample;
                sample.colour = colour[i];
                sample.photon = photon[i];
                sample.photon_inner = inner[i];
                sample.group = group;
                photon_total += sample.photon;
                inner_total += sample.photon_inner;
                ++counters.samples;
                check_pixel(sample.colour, x + i, y);
                const std::size_t pixel = static_cast<std::size_t>(y) * out.width + x + i;
                out.at(x + i, y) = accumulator.add(pixel, sample);
                for (std::size_t l = 0; l < layer_count; ++l) (*(*layers)[l].sums)[pixel] += glm::dvec3(layer_colour[l][i]);
            }
        }
    }
    counters.photon_value = photon_before + photon_total;
    counters.photon_value_inner = inner_before + inner_total;
}

ProgressiveAccumulator ProgressiveRender::summed_on_rank0(Cluster& cluster, const std::atomic<bool>& cancel) const {
    // A copy (the accumulation goes on), made before the checkpoint: nothing may fail between it
    // and the reduction.
    ProgressiveAccumulator all;
    std::exception_ptr error;
    try {
        all.reset(accumulator_.width(), accumulator_.height());
        all.sums() = accumulator_.sums();
    } catch (...) {
        error = std::current_exception();
    }
    cluster.checkpoint(error, &cancel);
    cluster.reduce_sum(all.sums());
    return all;
}

ErrorEstimate ProgressiveRender::combined_error(Cluster& cluster, const std::atomic<bool>& cancel) {
    // Every rank's sums added on rank 0, its estimate sent back.
    const ProgressiveAccumulator all = summed_on_rank0(cluster, cancel);
    ErrorEstimate e;
    if (cluster.rank() == 0) e = all.estimate_error();
    Cluster::Bytes bytes(sizeof e);
    std::memcpy(bytes.data(), &e, sizeof e);
    cluster.broadcast(bytes, 0);
    if (bytes.size() != sizeof e) throw std::runtime_error("the error estimate from rank 0 has the wrong size");
    std::memcpy(&e, bytes.data(), sizeof e);
    return e;
}

void ProgressiveRender::adapt_radii(Cluster* cluster, const std::atomic<bool>& cancel) {
    if (!cluster || cluster->size() <= 1) {
        accumulator_.adapt_radius_factors(state_.radius_factors, state_.adapted_sums);
        return;
    }
    // Every rank's sums on rank 0, which sends the factors back: every rank gathers with them.
    const ProgressiveAccumulator all = summed_on_rank0(*cluster, cancel);
    std::vector<float>& factors = state_.radius_factors;
    Cluster::Bytes bytes;
    if (cluster->rank() == 0) {
        all.adapt_radius_factors(factors, state_.adapted_sums);
        bytes.resize(factors.size() * sizeof(float));
        std::memcpy(bytes.data(), factors.data(), bytes.size());
    }
    cluster->broadcast(bytes, 0);
    const std::size_t pixels = static_cast<std::size_t>(accumulator_.width()) * static_cast<std::size_t>(accumulator_.height());
    if (bytes.size() != pixels * sizeof(float)) throw std::runtime_error("the radius factors from rank 0 have the wrong size");
    factors.resize(pixels);
    std::memcpy(factors.data(), bytes.data(), bytes.size());
}

void ProgressiveRender::walk_radius_sequence(int pass, double alpha) {
    while (state_.scale_pass < pass) {  // the same sequence of roundings whichever rank walks it
        state_.scale2 = next_radius2(state_.scale2, state_.scale_pass + 1, alpha);
        ++state_.scale_pass;
    }
}

void ProgressiveRender::balance_radii(const ErrorEstimate& e, int pass, double alpha) {
    // Pass i at r^2 s has s times the blur and 1/s times the variance of one at r^2 (a disc's blur
    // grows as r^2, its photon count too). With the estimate's noise n and blur b over the caustic
    // region, taken as if every pass so far had gathered at the present s, the passes so far err
    // least when s' = s (n^2 / 2 b^2)^(1/3): the squared blur half the variance of the mean. With
    // alpha = 2/3 the Knaus-Zwicker sequence shrinks both alike from there, so the balance holds
    // (docs/CAUSTICS.md, "The radius, balanced"). Earlier passes at other radii weigh less at each
    // update (4, 8, 16, ...), so the updates settle where the whole accumulation is balanced. A
    // step grows r^2 by at most 2 (a blur read as 0 among the first passes' noise included) and
    // shrinks it by at most 16.
    // Every rank walks the sequence to the same pass before scaling it: the same bits.
    walk_radius_sequence(pass, alpha);
    if (!e.known || !(e.noise > 0.0)) return;
    constexpr double max_growth = 2.0, max_shrink = 16.0, max_scale2 = 16.0;
    const double balance = e.bias > 0.0 ? e.noise * e.noise / (2.0 * e.bias * e.bias) : max_growth * max_growth * max_growth;
    const double step = std::clamp(std::cbrt(balance), 1.0 / max_shrink, max_growth);
    state_.scale2 = std::min(max_scale2, state_.scale2 * step);
}

void ProgressiveRender::run(RenderHost& host, const ShadingSetup& setup, const TileContext& context) {
    // Progressive photon mapping, memoryless (Knaus & Zwicker 2011; docs/CAUSTICS.md): pass i
    // shoots a fresh photon stream and gathers within radius r_i, r_{i+1}^2 = r_i^2 (i + alpha) /
    // (i + 1); each pixel averages its passes' jittered samples. Noise and bias both vanish as
    // passes grow, in memory fixed by the image size. r_1 at a gather is --accumulation-radius
    // pixel footprints there (the path length from the camera times a pixel's angle; at most the
    // maximum distance): the blur starts below a few pixels wherever the caustic is seen. alpha is
    // 2/3 unless --radius-alpha says otherwise (1: a fixed radius, whose image converges to that
    // radius's blur: the stored references are made so).
    // No pass depends on another, so passes can run anywhere: with K ranks the passes go in
    // rounds, rank k running pass round K + k. Their integer sums add up to one process's.
    const RenderJob& job = host.job();
    const Options& options = job.options;
    const double alpha = options.radius_alpha;
    Cluster* const cluster = host.cluster();
    const bool shared = cluster && cluster->size() > 1;
    const std::atomic<bool>& cancel = host.cancel_flag();
    const int ranks = shared ? cluster->size() : 1, rank = shared ? cluster->rank() : 0;
    State& acc = state_;
    const bool resumed = acc.valid && !shared;
    // --layers: sums from the accumulation's first pass, or none (a continued accumulation that had
    // none, or a pass without them, has no layers to give).
    const bool with_layers = options.layers && host.renders_layers() && !shared && (!resumed || !layer_sums_.empty());
    if (!with_layers) layer_sums_.clear();
    if (!resumed) {
        accumulator_.reset(job.width, job.height);
        if (with_layers)
            layer_sums_.assign(std::size(written_layers),
                               std::vector<glm::dvec3>(static_cast<std::size_t>(job.width) * job.height));
        acc = State{};
        acc.valid = !shared;  // the ranks' sums are added up at the end: nothing to resume
        acc.seed = context.seed;
        restored_ = false;
        emission_weights_.clear();
    }
    const int limit = options.pass_limit();  // 0 = none
    const double segment_start = now_seconds(), seconds_before = acc.seconds;
    auto elapsed = [&] { return seconds_before + host.elapsed_seconds(); };
    const int coarse_block = resumed ? 0 : host.coarse_preview_block();
    const std::size_t tile_count = host.tiles().size();
    // With a render region, passes go to its pixels alone; the others keep their sums and their
    // pixels, and the error (and its stopping rule) is the region's (docs/PREVIEW.md, "Render region").
    const RenderRegion region = host.region();
    if (resumed && !(acc.region == region)) acc.error = accumulator_.estimate_error(region);
    acc.region = region;
    host.report([&](SessionProgress& progress, RenderStats&) {
        progress.accumulating = true;
        progress.pass_limit = limit;
        progress.passes_done = acc.next_pass;
        progress.photons_emitted = acc.photons_emitted;
        progress.samples_per_pixel = acc.next_pass;
        progress.radius = acc.radius;
        progress.error = acc.error;
        progress.accumulated_seconds = acc.seconds;
        // Tiles count per pass (a direct-light preview already shown included); the total grows
        // with the passes when no limit is set.
        const int shown = host.direct_preview_shown() ? 1 : 0;
        const int coarse = coarse_block > 0 ? 1 : 0;
        const int planned = limit > 0 ? std::max(1, (limit - acc.next_pass + ranks - 1) / ranks) : 1;
        progress.passes = shown + coarse + planned;
        progress.tiles_total = tile_count * static_cast<std::size_t>(progress.passes);
    });
    const CausticStage* const first_stage = host.photon_stage();
    const bool has_photons = first_stage && first_stage->photon_pass;
    Image& image = host.image();
    if (restored_) {  // a saved accumulation: its image at once, even when no pass is left to add
        publish_means(host, accumulator_, image);
        restored_ = false;
    }
    if (coarse_block > 0) {
        host.run_tiles("preview", 0, [&](std::size_t, const Tile& tile, RayCounters& c) {
            if (const Tile part = region_part(tile, region); !tile_empty(part))
                render_coarse_tile(context, part, coarse_block, image, c);
        });
    }
    // What pass p gathers with: its photons in a grid, the first radius scaled by (r_p / r_1).
    struct PassShading {
        ShadingSetup setup;
        ProgressiveParams params;
    };
    auto pass_setup_for = [&](int p) {
        walk_radius_sequence(p, alpha);
        PassShading pass{setup, ProgressiveParams::from(options)};
        pass.setup.caustic_map = nullptr;
        pass.params.caustic_grid = has_photons ? &grid_ : nullptr;
        pass.params.footprint_radius = static_cast<float>(options.accumulation_radius) * setup.dot_radius_per_distance;
        // One random point of each area light per pass: soft shadows converge over the passes
        // like everything else, with no grid pattern and n^2 fewer shadow rays a pass.
        pass.setup.shadow_grid = 1;
        pass.params.radius_scale = static_cast<float>(std::sqrt(acc.scale2));
        return pass;
    };
    // The grid's cells are made for the radius most gathers use (a function of the scene and the
    // pass alone: every rank sorts a pass's photons into the same cells, so sums are the same bits).
    // One measured while cancelled is not the scene's: alone, the loop below stops at once and a
    // resume measures it again; with other ranks, the round's checkpoint stops every rank.
    if (has_photons && acc.typical_radius <= 0.0) {
        const double radius = typical_first_radius(host.scene(), *context.camera, job, setup);
        if (shared || !cancel) acc.typical_radius = radius;
    }
    // --guided-emission: the cells' weights from the first pass's photons, learnt before the first
    // pass that shoots with them, once per accumulation (again after a resume: they are a function
    // of the first pass, the camera and the options, so every rank learns the same bits).
    auto learn_weights = [&] {
        if (!options.guided_emission || !emission_weights_.empty() || !(acc.typical_radius > 0.0)) return;
        const auto t_learn = std::chrono::steady_clock::now();
        EmissionView view;
        view.eye = glm::vec3(job.camera.eye);
        view.radius_per_distance = static_cast<float>(options.accumulation_radius) * setup.dot_radius_per_distance;
        view.max_radius = static_cast<float>(options.effective_caustic_max_dist());
        view.grid_cell = static_cast<float>(grid_cell_factor * acc.typical_radius);
        emission_weights_ = learn_emission_weights(*first_stage, view, grid_, &cancel);
        host.add_stage_time("photon passes", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_learn).count());
    };
    double last_round_seconds = 0.0, radius_log_before = 0.0, grid_seconds = 0.0;
    std::uint64_t radius_samples_before = 0;
    int next_error_check = 0;  // shared: the round whose end estimates the error (with --target-error)
    // Alone, the estimate reads every pixel's sums: after every pass for --target-error and for
    // the first 8 passes (it is known from the second), later when a quarter second and ten
    // times its own cost have passed since the last (what the progress line and the preview
    // show), and once more at the end if passes came after it.
    double next_estimate_at = 0.0;
    bool estimate_stale = false;
    std::string stopped_by = "passes";
    for (int round = 0;; ++round) {
        const int base = acc.next_pass;
        if (cancel && !shared) {
            stopped_by = "cancelled";
            break;
        }
        if ((limit > 0 && base >= limit) || base >= max_accumulated_passes) break;  // the sums' capacity
        if (options.target_error > 0.0 && acc.error.known && base >= 4 && acc.error.relative <= options.target_error) {
            stopped_by = "target error";
            break;
        }
        // No round that would end past the time limit (predicted from the last one); at least one.
        // With ranks, the slowest rank's times decide, the same on every rank.
        // (Asked only after a round: its end was a checkpoint every rank passed.)
        if (options.time_limit > 0.0 && base > 0 &&
            (shared ? cluster->all_max(elapsed()) : elapsed()) + last_round_seconds > options.time_limit) {
            stopped_by = "time";
            break;
        }
        // The radius factors change between passes every rank has finished: before pass 8, 32,
        // 128, ... (a round with ranks ends there), from the sums of all the passes before; the
        // balanced radius's scale likewise, before pass 4, 8, 16, ...
        const bool adapting = options.adaptive_radius && has_photons, balancing = options.auto_radius && has_photons;
        if (balancing && base > 0 && balance_after(base - 1) == base) {
            // Alone, the estimate of the last round serves unless it was skipped; with ranks, every
            // rank's sums are added for it.
            if (shared) {
                balance_radii(combined_error(*cluster, cancel), base, alpha);
            } else {
                if (estimate_stale) acc.error = accumulator_.estimate_error(region);
                estimate_stale = false;
                balance_radii(acc.error, base, alpha);
            }
        }
        if (adapting && base > 0 && adaptation_after(base - 1) == base) adapt_radii(shared ? cluster : nullptr, cancel);
        int round_end = base + ranks;
        if (const int next = adapting ? adaptation_after(base) : 0; next > 0) round_end = std::min(round_end, next);
        if (const int next = balancing ? balance_after(base) : 0; next > 0) round_end = std::min(round_end, next);
        const int p = base + rank;
        const bool mine = (limit == 0 || p < limit) && p < round_end;
        const double t0 = now_seconds();
        std::unique_ptr<CausticStage> fresh;
        long long round_photons = 0;
        if (mine) {
            const std::vector<Photon>* photons = has_photons ? &first_stage->photons : nullptr;
            if (p > 0 && has_photons) {
                learn_weights();
                PhotonPassExtras extras;
                extras.seed = hash_combine(acc.seed ^ 0x7061737365730000ULL, static_cast<std::uint64_t>(p));
                extras.first = first_stage;
                extras.progress = &host.photon_progress();
                extras.photons_only = true;
                extras.pass = p / replicate_groups;
                extras.group = p % replicate_groups;
                extras.reuse = &spare_photons_;
                extras.emission_weights = options.guided_emission && !emission_weights_.empty() ? &emission_weights_ : nullptr;
                host.photon_progress() = 0;
                host.report([&](SessionProgress& progress, RenderStats&) {
                    progress.photons_done = 0;
                    progress.photons_total = progressive_photon_directions(job);
                });
                fresh = std::make_unique<CausticStage>();
                host.set_stage("shooting photons");
                build_progressive_pass(*fresh, host.scene(), job, &cancel, extras);
                if (cancel && !shared) {
                    stopped_by = "cancelled";
                    break;
                }
                photons = &fresh->photons;
            }
            const PassShading pass_shading = pass_setup_for(p);
            if (photons) {
                const auto t_grid = std::chrono::steady_clock::now();
                grid_.build(*photons, static_cast<float>(grid_cell_factor * acc.typical_radius * std::sqrt(acc.scale2)));
                grid_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_grid).count();
                round_photons = photon_directions(fresh ? *fresh : *first_stage);
            }
            const float* const factors = acc.radius_factors.empty() ? nullptr : acc.radius_factors.data();
            const ProgressiveIntegrator pass_integrator(pass_shading.setup, pass_shading.params);
            // --layers: one integrator per layer, on the pass's photons and radii.
            std::vector<ProgressiveIntegrator> layer_integrators;
            std::vector<AccumulatedLayer> layer_targets;
            layer_integrators.reserve(layer_sums_.size());  // the targets point into it
            for (std::size_t l = 0; l < layer_sums_.size(); ++l) {
                ShadingSetup layer_setup = pass_shading.setup;  // the integrator keeps its own copy
                layer_setup.layer = written_layers[l];
                layer_integrators.emplace_back(layer_setup, pass_shading.params);
                layer_targets.push_back({&layer_integrators[l], &layer_sums_[l]});
            }
            const std::vector<AccumulatedLayer>* const layer_list = layer_targets.empty() ? nullptr : &layer_targets;
            TileContext pass_context = context;
            pass_context.integrator = &pass_integrator;
            pass_context.seed = acc.seed;
            if (round > 0 && limit == 0) {  // one more pass to show: the tile total grows
                host.report([&](SessionProgress& progress, RenderStats&) {
                    ++progress.passes;
                    progress.tiles_total += tile_count;
                });
            }
            if (!(shared && cancel))
                host.run_tiles("progressive passes", p, [&](std::size_t, const Tile& tile, RayCounters& c) {
                    if (const Tile part = region_part(tile, region); !tile_empty(part))
                        render_accumulation_tile(pass_integrator, pass_context, part, p, factors, accumulator_, image, c,
                                                 layer_list);
                });
        }
        double round_seconds = now_seconds() - t0;
        if (shared) {  // the round's end: every rank's state, photons and time
            cluster->checkpoint(nullptr, &cancel);
            round_photons = cluster->all_sum(round_photons);
            round_seconds = cluster->all_max(round_seconds);
        }
        // Pass p + 1 (1-based) has been averaged, wholly or (cancelled) in part: its pixels keep
        // their sample, the next pass is new.
        acc.next_pass = limit > 0 ? std::min(limit, round_end) : round_end;
        acc.photons_emitted += round_photons;
        if (!shared) {
            const double start = now_seconds();
            estimate_stale = options.target_error <= 0.0 && acc.next_pass > 8 && start < next_estimate_at;
            if (!estimate_stale) {
                acc.error = accumulator_.estimate_error(region);
                const double end = now_seconds();
                next_estimate_at = end + std::max(0.25, 10.0 * (end - start));
            }
        } else if (options.target_error > 0.0 && round >= next_error_check) {
            // Adding every rank's sums costs time (116 bytes a pixel through the network): every
            // round up to 256 K pixels, every 4th at a megapixel, every 32nd at 4K, at most every
            // 64th. Fixed by the image size, so that --reproducible stops after the same pass.
            acc.error = combined_error(*cluster, cancel);
            const std::size_t pixels = static_cast<std::size_t>(job.width) * static_cast<std::size_t>(job.height);
            next_error_check = round + static_cast<int>(std::clamp<std::size_t>(pixels >> 18, 1, 64));
        }
        if (cancel && !shared) {
            stopped_by = "cancelled";
            break;
        }
        // The radius where the pass gathered (geometric mean over its gathers, for reports).
        const RayCounters pass_total = host.ray_totals();
        const double radius = pass_total.radius_samples > radius_samples_before
                                  ? std::exp((pass_total.radius_log_sum - radius_log_before) /
                                             static_cast<double>(pass_total.radius_samples - radius_samples_before))
                                  : 0.0;
        radius_log_before = pass_total.radius_log_sum;
        radius_samples_before = pass_total.radius_samples;
        if (base == 0) acc.first_radius = radius;
        acc.radius = radius;
        last_round_seconds = round_seconds;
        host.report([&](SessionProgress& progress, RenderStats& stats) {
            progress.passes_done = acc.next_pass;
            progress.photons_emitted = acc.photons_emitted;
            progress.accumulated_seconds = seconds_before + (now_seconds() - segment_start);
            progress.samples_per_pixel = acc.next_pass;
            progress.radius = acc.radius;
            progress.error = acc.error;
            if (fresh) {
                stats.caustic_lights = fresh->lights;
                stats.caustic_photons = fresh->photons.size();
                stats.caustic_map_bytes = grid_.memory_bytes();
            }
        });
        if (fresh || grid_seconds > 0.0)
            host.add_stage_time("photon passes", (fresh ? fresh->map_seconds + fresh->shoot_seconds : 0.0) + grid_seconds);
        if (fresh) spare_photons_ = std::move(fresh->photons);  // the next pass's buffer
        grid_seconds = 0.0;
        if (!shared) snapshot_if_asked(seconds_before + (now_seconds() - segment_start));
    }
    if (shared) {
        // Every rank's sums on rank 0, which makes the image and the estimate one process makes.
        cluster->checkpoint(nullptr, &cancel);
        cluster->reduce_sum(accumulator_.sums());
        if (rank == 0) {
            acc.error = accumulator_.estimate_error();
            publish_means(host, accumulator_, image);
        }
    }
    std::vector<Photon>().swap(spare_photons_);  // nothing held between renders
    if (estimate_stale) acc.error = accumulator_.estimate_error(region);
    acc.seconds = seconds_before + (now_seconds() - segment_start);
    host.report([&](SessionProgress& progress, RenderStats& stats) {
        if (estimate_stale) progress.error = acc.error;
        progress.stopped_by = stopped_by;
        progress.accumulated_seconds = acc.seconds;
        if (shared) progress.error = acc.error;  // from every rank's sums (one process's: the last pass's)
        RenderStats::Accumulation& a = stats.accumulation;
        a.passes = acc.next_pass;
        a.first_radius = acc.first_radius;
        a.radius = acc.radius;
        a.photons_emitted = acc.photons_emitted;
        a.error = acc.error.known ? acc.error.relative : -1.0;
        a.noise = acc.error.noise;
        a.bias = acc.error.bias;
        a.bytes = accumulator_.memory_bytes() + acc.radius_factors.capacity() * sizeof(float) +
                  acc.adapted_sums.capacity() * sizeof(std::int64_t);
        for (const std::vector<glm::dvec3>& sums : layer_sums_) a.bytes += sums.capacity() * sizeof(glm::dvec3);
        a.stopped_by = stopped_by;
    });
}

}  // namespace caustica
