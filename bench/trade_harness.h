// The speed-against-accuracy harness of bench/trade (docs/ACCURACY.md): its scenes with their
// references, the sweep of photon count x N x maximum gather distance, and the quality presets,
// each run timed and its caustic error measured. bench/trade.cpp drives it and writes the outputs.
#pragma once

#include "bench/trade_reference.h"
#include "core/render/image.h"
#include "core/render/image_error.h"
#include "core/scene/options.h"
#include "core/scene/scene_desc.h"

#include <cstddef>
#include <string>
#include <vector>

namespace caustica::trade {

/// The default maximum gather distance, 0.15 x unit distance: every scene here has unit distance 1.
inline constexpr double default_max_dist = 0.15;

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

/// The Lua scenes with stored references (assets/references/), and how each reference is made.
extern const std::vector<ReferenceRecipe> recipes;

/// A scene of the sweep, ready to render, with its reference and caustic region.
struct TradeScene {
    std::string name;
    RenderJob job;                    ///< harness resolution, caustics only, one sample per pixel
    Image reference;
    std::vector<std::size_t> region;  ///< pixel indices of the caustic region
    std::string reference_kind;       ///< "analytic" or the reference file
    /// The reference's own noise (relative RMSE over the caustic region; 0: none or unknown). A
    /// run's error against it is sqrt(true^2 + noise^2) on average, the two being independent.
    double reference_noise = 0.0;
    std::vector<long long> sweep, quick_sweep;  ///< photon counts of the full and --quick sweeps
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

/// One preset measured on one scene: caustic error and times, and the full image's render time.
struct PresetRow {
    std::string scene, preset;
    Options options;
    Timing caustics;
    double full_render_seconds = 0.0;
    ImageError error;
};

/// The settings every measured run shares: caustics only, one centred sample (an accumulating run
/// jitters whatever disable_aa says), fixed streams, `threads` threads, and the progressive
/// integrator, whose physics the references (and the analytic virtual light) follow.
void set_caustics_only(Options& options, int threads);

/// A Lua scene's first render at the recipe's resolution, caustics only (set_caustics_only).
RenderJob load_lua_job(const ReferenceRecipe& recipe, int threads);

/// What a stored reference of `job` (made from `script`) must say it was made with.
ReferenceInfo recipe_info(const std::string& script, const RenderJob& job, long long photons, int neighbours,
                          double max_dist, int runs);

/// Renders and stores the reference of one Lua scene (build/trade --make-references: minutes).
void make_reference(const ReferenceRecipe& recipe, int threads);

/// The virtual-light scene, with its analytic reference (the light's real caustic).
TradeScene virtual_light(int threads);

/// Loads a Lua scene and its stored reference; returns false (with a message) when the reference
/// is missing or stale.
bool lua_scene(const ReferenceRecipe& recipe, int threads, TradeScene& scene);

/// The sweep of one scene: each photon count is shot once per repetition and every (max distance,
/// N) is gathered from it; times are medians over repetitions (errors do not vary: --reproducible).
std::vector<Row> sweep(const TradeScene& scene, const std::vector<long long>& counts, const std::vector<int>& ns,
                       const std::vector<double>& max_dists, int repeat);

/// The quality presets (draft, preview, final) measured on one scene.
std::vector<PresetRow> measure_presets(const TradeScene& scene, int repeat);

}  // namespace caustica::trade
