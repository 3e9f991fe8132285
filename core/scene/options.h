// Render options: one table drives the command line, gr.option, --help and the PNG metadata.
#pragma once

#include "core/io/image_io.h"
#include "core/integrators/shading_layer.h"
#include "core/io/tonemap.h"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace caustica {

/// How projection maps are used when shooting caustic photons.
enum class ProjectionMapMode { automatic, on, off };

/// Which light transport renders the image (the original's, docs/CAUSTICS.md, or our own).
enum class IntegratorKind {
    classic,      ///< the original renderer's rules, rule for rule (the default)
    progressive,  ///< our physically motivated photon mapper
};

/// Every option of SCENE_API.md plus ours, with the original's defaults.
struct Options {
    // conventions and reporting
    bool a4 = false;           ///< course conventions (pre-multiplied transforms, unit cube)
    bool timing = false;       ///< -t: per-stage times
    bool silent = false;       ///< -s: no progress, no messages but errors
    bool stats = false;        ///< -S: statistics
    bool verbose = false;      ///< -v
    bool debug = false;        ///< -d
    // feature switches
    bool disable_aa = false;
    bool disable_bv = false;       ///< analytic primitives without bounding volumes (each ray tests all)
    bool disable_csg_bb = false;
    bool draw_aa = false;          ///< mark supersampled pixels
    bool draw_caustic_map = false;
    bool draw_caustic_prm = false;   ///< the original's flag: accepted, changes nothing (its renders were plain)
    bool show_projection_map = false;  ///< tint what the projection maps aim photons at
    bool draw_caustics_only = false;
    bool no_caustic_map = false;
    bool no_soft_shadows = false;
    bool reproducible = false;     ///< fixed random streams: identical output for any thread count
    bool rays = false;             ///< orange sunburst background instead of the miss colour
    bool gi = false;               ///< global-illumination photon map (classic)
    bool draw_gi_map = false;      ///< GI photons as dots (implies the GI map)
    bool draw_gi_only = false;     ///< only the GI estimate (implies the GI map)
    ShadingLayer show_layer = ShadingLayer::beauty;  ///< --show-layer: the image holds one layer of its light
    bool srgb = false;             ///< encode sRGB in the PNG (default: clamp, linear, as the original)
    bool layers = false;           ///< --layers: also render the light split into layers (a multilayer EXR)
    int resolution_override = 0;   ///< --minres/--lores/--midres/--hires: square size, 0 = as scripted
    Tonemap tonemap = Tonemap::clamp;  ///< --tonemap: PNG only (the default clamps, as the original)
    double exposure = 0.0;         ///< --exposure: stops, every output format
    ExrPixel exr_pixel = ExrPixel::half;  ///< --exr-pixel: channel type of EXR output
    // values
    int threads = 0;               ///< 0 = all cores
    int aa_grid = 3;
    double aa_threshold = 0.5;
    long long caustic_num_photons = 0;
    int caustic_num_neighbours = 5;
    long long gi_num_photons = 1'000'000;
    int gi_num_neighbours = 100;
    IntegratorKind integrator = IntegratorKind::classic;
    int caustic_pm_gran = 180;
    double caustic_max_dist = -1.0;  ///< < 0: 0.15 x unit distance
    double accumulation_radius = 3.0;  ///< progressive accumulation: first gather radius in pixel footprints
    /// progressive accumulation: r^2_{i+1} = r^2_i (i + alpha) / (i + 1); 1 keeps the first radius
    double radius_alpha = 2.0 / 3.0;
    ProjectionMapMode projection_map = ProjectionMapMode::automatic;
    int shadow_grid = 4;
    double unit_distance = 1.0;
    double energy_fudge = 1.0;
    bool caustic_cone_filter = false;  ///< Jensen's cone filter instead of the plain disc average
    bool photon_random_emission = false;  ///< independent random photon directions instead of low-discrepancy
    bool adaptive_radius = false;  ///< progressive: each pixel's radius balances its blur and noise
    bool auto_radius = false;      ///< progressive: one factor on every radius balances the image's blur and noise
    bool photon_split = false;     ///< progressive: split photons at mirrors and glass instead of roulette
    bool guided_emission = true;   ///< progressive: weight the projection map's cells by what their photons add to the image
    /// progressive: each pass shoots enough directions that about this many photons per image pixel
    /// are traced, shared by the lights (0: the photon count as given)
    double photons_per_pixel = 0.0;
    int max_depth = 8;             ///< recursion limit for reflection/refraction
    double min_weight = 1e-3;      ///< stop a ray path when its weight falls below this
    /// progressive: a ray path whose weight falls below this continues with probability
    /// weight / roulette_weight, carrying roulette_weight (0: every path above min_weight traced)
    double roulette_weight = 0.05;
    double script_timeout = 60.0;  ///< seconds of script evaluation, 0 = none
    long long script_memory_mib = 2048;  ///< budget of the script (Lua heap + what it makes C++ hold), 0 = none
    long long render_memory_mib = 0;     ///< budget of what the renderer builds, 0 = default_render_memory_bytes()
    long long seed = 0;            ///< base of the random streams
    /// Progressive photon mapping: passes of fresh photons and pixel samples averaged with a
    /// shrinking radius. 1 = the single k-nearest pass; 0 = until another rule stops it. Read the
    /// limit in effect with pass_limit().
    int passes = 1;
    bool passes_given = false;     ///< --passes was given (else --time or --target-error alone mean "until that rule")
    double time_limit = 0.0;       ///< progressive: no pass that would end past this many seconds (0 = no limit)
    double target_error = 0.0;     ///< progressive: stop once the estimated relative error is below (0 = none)

    /// The maximum photon gather distance in effect (resolves the "0.15 x unit distance" default).
    double effective_caustic_max_dist() const {
        return caustic_max_dist < 0.0 ? 0.15 * unit_distance : caustic_max_dist;
    }

    /// The renderer's memory budget in bytes: --render-memory, or default_render_memory_bytes().
    double render_memory_bytes() const;

    /// Whether a debug view replaces the shading (--draw-aa, --draw-caustic-map,
    /// --show-projection-map, --draw-caustics-only, --draw-gi-map, --draw-gi-only).
    bool debug_view() const {
        return draw_aa || draw_caustic_map || show_projection_map || draw_caustics_only || draw_gi_map || draw_gi_only;
    }
    /// Whether the GI photon map is wanted (--gi or one of its debug views).
    bool gi_wanted() const { return gi || draw_gi_map || draw_gi_only; }
    /// The pass limit in effect (0 = none): --passes when given (or set to anything but 1); else
    /// none when --time or --target-error is set ("--time 60" alone renders for 60 s), else one.
    int pass_limit() const {
        if (passes_given || passes != 1) return passes;
        return time_limit > 0.0 || target_error > 0.0 ? 0 : 1;
    }
    /// Whether the progressive integrator accumulates passes (a stopping rule other than one pass).
    bool accumulates() const {
        return integrator == IntegratorKind::progressive && (passes != 1 || time_limit > 0.0 || target_error > 0.0);
    }
};

/// What the renderer may build when --render-memory is 0: 60% of the machine's physical memory
/// (docs/RELIABILITY.md, "Bounded memory").
double default_render_memory_bytes();

/// The stages of a render that an option's value feeds. RenderSession caches each stage by the
/// options that feed it (and by the scene), so a change re-runs the stages it feeds and every
/// stage after them: scene -> photons -> image -> output. Each row of the option table declares
/// its stages; tests/scene/test_option_stages.cpp checks every option against what actually
/// re-runs and what actually changes.
enum OptionStage : unsigned {
    stage_none = 0,     ///< reporting, threads, the script's own limits: nothing rendered changes
    stage_scene = 1,    ///< flattening and the BVH
    stage_photons = 2,  ///< the photon maps and their projection maps
    stage_image = 4,    ///< the image passes (and the progressive accumulation)
    stage_output = 8,   ///< the written file: tone curve, exposure, encoding
};

/// Every long option name with the stages it declares; a preset (--quality) sets other options
/// and declares what they feed. `cache_key` is what the scene and photon stages see of its value:
/// the value itself, except for the GI views, which all mean "the GI map is wanted" there.
struct OptionStages {
    std::string name;
    unsigned stages = stage_none;
    bool preset = false;
    std::function<std::string(const Options&)> cache_key;
};
std::vector<OptionStages> option_stages();

/// Folds into `h` the value of every option (presets excepted) that feeds `stage`: the part of a
/// stage's cache key that options make (for the scene and photon stages, their `cache_key`).
std::uint64_t hash_options_feeding(std::uint64_t h, const Options& options, unsigned stage);

/// Applies command-line style tokens ("--aa-grid", "4", "-S", "--threads=2") to `options`.
/// Throws InputError naming the option on unknown options (suggesting the closest), missing or
/// bad values. Non-option tokens are an error unless `positional` is given, which collects them.
/// `names_set`, when given, receives the long name of every option the tokens set ("-St": both).
void apply_option_tokens(Options& options, const std::vector<std::string>& tokens,
                         std::vector<std::string>* positional = nullptr,
                         std::vector<std::string>* names_set = nullptr);

/// Splits a gr.option string into tokens on white space (quotes group words).
std::vector<std::string> split_option_string(std::string_view text);

/// The option list for --help, one option a line, grouped.
std::string options_help();

/// "--name value ..." for every option that differs from the defaults (PNG metadata, logs).
std::string describe_non_default(const Options& options);

/// Refuses, with InputError, stopping rules `caustica render` could never end: a progressive
/// accumulation with --passes 0 and neither --time nor --target-error.
void check_render_stop_rules(const Options& options);
/// Refuses --show-layer (other than image) with a debug view, which would replace the shading the
/// layer is part of (InputError).
void check_shown_layer(const Options& options);

/// Levenshtein distance, for "did you mean" suggestions.
int edit_distance(std::string_view a, std::string_view b);

}  // namespace caustica
