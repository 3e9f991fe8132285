// Progressive photon mapping in bench/trade (docs/ACCURACY.md): the error of an accumulating render
// (--passes) against time, checkpointed at 1, 2, 4, ... passes of one accumulation, with the
// renderer's own error estimate beside the true error; and the pixel-averaged references that a
// jittered accumulation converges to.
#pragma once

#include "bench/trade_harness.h"

#include <string>
#include <vector>

namespace caustica::trade {

/// The settings of one progressive curve (negative or 0: the scene's own value).
struct ProgressiveRun {
    long long photons = 0;  ///< photon directions per light, per pass
    double radius = 0.0;    ///< --accumulation-radius: the first radius in pixel footprints (0: the default)
    double max_dist = 0.0;  ///< cap of the first radius
    bool split = false;     ///< --photon-split on
    bool adaptive_radius = false;  ///< --adaptive-radius on
    bool auto_radius = false;      ///< --auto-radius on
    int guided_emission = -1;      ///< --guided-emission: 1 on, 0 off, -1 the default
    double photons_per_pixel = 0.0;  ///< --photons-per-pixel K (0: the photons as given)
    int max_passes = 256;   ///< last checkpoint (a power of 2 or not: it is always measured)
    double max_seconds = 0.0;  ///< stop the checkpoints once this much render time is spent (0: none)
    std::string png_path;      ///< when set, the last checkpoint's image is written there (clamped linear)
};

/// One checkpoint of an accumulation.
struct ProgressivePoint {
    int passes = 0;
    double seconds = 0.0;       ///< photon stages + image passes, summed from the start (no scene build)
    ImageError error;           ///< against the reference
    double rel_rmse_less_noise = 0.0;  ///< error.rel_rmse with the reference's own noise taken out in quadrature
    double estimate = -1.0;     ///< the renderer's estimated relative error (< 0: unknown)
    double noise = 0.0, bias = 0.0;  ///< its two parts
    double first_radius = 0.0, radius = 0.0;
    long long photons_emitted = 0;
};

/// Renders one accumulation of `scene` (its job's resolution, caustics only, jittered samples) and
/// measures it at passes 1, 2, 4, ... up to run.max_passes (or run.max_seconds).
std::vector<ProgressivePoint> progressive_curve(const TradeScene& scene, const ProgressiveRun& run);

/// The virtual light's analytic reference averaged over each pixel (what a jittered accumulation
/// converges to), from `passes` jittered samples of the mirrored light's direct illumination.
Image pixel_averaged_virtual_light(const TradeScene& scene, int passes, int threads);

/// How a pixel-averaged reference of a Lua scene is made: two long accumulations at a fixed radius
/// (--radius-alpha 1), averaged.
struct ProgressiveRecipe {
    const char* name;    ///< of the ReferenceRecipe whose scene it renders
    int width, height;
    long long photons;   ///< per pass
    double radius;       ///< --accumulation-radius, kept for every pass
    double max_dist;
    int passes;          ///< in all: two accumulations (seeds 1, 2) of passes / 2 each
};

/// The progressive references (assets/references/NAME_progressive.pfm).
extern const std::vector<ProgressiveRecipe> progressive_recipes;

/// Renders and stores one progressive reference (build/trade --make-references --progressive).
void make_progressive_reference(const ProgressiveRecipe& recipe, int threads);

/// Loads a Lua scene at the progressive reference's resolution with that reference; false (with
/// a message) when it is missing or stale.
bool progressive_lua_scene(const ProgressiveRecipe& recipe, int threads, TradeScene& scene);

/// The time of one progressive pass of a Lua scene's full image (not caustics only) at
/// width x height with the scene's own options (target: the preview should show a new pass at
/// least twice a second at 1280 x 720): renders `passes` passes and prints the stage times per pass,
/// the photons traced per pass and per second of the photon stages, and the radiance estimates' share.
void pass_timing(const char* scene_name, int width, int height, int passes, int threads);

/// Least-squares slope of log10(y) on log10(x).
double log_log_slope(const std::vector<std::pair<double, double>>& points);

}  // namespace caustica::trade
