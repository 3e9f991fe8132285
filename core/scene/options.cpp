#include "core/scene/options.h"

#include "core/scene/source_location.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <unistd.h>

namespace caustica {
namespace {

/// One row of the option table.
struct OptionSpec {
    OptionSpec(std::string long_name_, char short_name_, const char* value_name_, const char* group_, const char* help_,
               std::function<void(Options&, const std::string&)> set_, std::function<std::string(const Options&)> get_)
        : long_name(std::move(long_name_)), short_name(short_name_), value_name(value_name_), group(group_),
          help(help_), set(std::move(set_)), get(std::move(get_)) {}

    std::string long_name;   ///< without "--"
    char short_name;         ///< 0 when none
    const char* value_name;  ///< nullptr for a flag
    const char* group;
    const char* help;
    std::function<void(Options&, const std::string&)> set;   ///< value is "" for flags
    std::function<std::string(const Options&)> get;         ///< current value as text
    unsigned stages = stage_none;  ///< the OptionStage bits its value feeds
    bool preset = false;           ///< sets other options (its value is theirs): not part of a cache key
    std::function<std::string(const Options&)> cache_key;  ///< what the scene and photon stages see (empty: get)

    OptionSpec feeds(unsigned s) && {
        stages = s;
        return std::move(*this);
    }
    /// The same, where the scene and photon stages see only `key` of its value.
    OptionSpec feeds(unsigned s, std::function<std::string(const Options&)> key) && {
        stages = s;
        cache_key = std::move(key);
        return std::move(*this);
    }
    OptionSpec preset_of(unsigned s) && {
        stages = s;
        preset = true;
        return std::move(*this);
    }
};

std::string format_double(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

long long parse_integer(const std::string& name, const std::string& text, long long lo, long long hi,
                        const char* why = nullptr) {
    long long v = 0;
    // Accept plain integers and exact scientific forms like 1e6.
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size()) {
        double d = 0.0;
        auto [dend, dec] = std::from_chars(text.data(), text.data() + text.size(), d);
        if (dec != std::errc() || dend != text.data() + text.size() || !std::isfinite(d) ||
            d != std::floor(d) || std::fabs(d) > 9.0e18)
            throw InputError("--" + name + ": expected a whole number, got '" + text + "'");
        v = static_cast<long long>(d);
    }
    if (v < lo || v > hi)
        throw InputError("--" + name + ": " + text + " is out of range [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]" + (why ? std::string(": ") + why : std::string()));
    return v;
}

double parse_real(const std::string& name, const std::string& text, double lo, double hi, bool lo_open) {
    double v = 0.0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size())
        throw InputError("--" + name + ": expected a number, got '" + text + "'");
    if (!std::isfinite(v)) throw InputError("--" + name + ": " + text + " is not a finite number");
    if (v < lo || v > hi || (lo_open && v == lo))
        throw InputError("--" + name + ": " + text + " is out of range " + (lo_open ? "(" : "[") +
                         format_double(lo) + ", " + format_double(hi) + "]");
    return v;
}

OptionSpec flag(std::string name, char short_name, const char* group, const char* help, bool Options::*member) {
    return {std::move(name), short_name, nullptr, group, help,
            [member](Options& o, const std::string&) { o.*member = true; },
            [member](const Options& o) { return std::string(o.*member ? "on" : "off"); }};
}

/// An integer option in [lo, hi]; `why` (optional) says in the range error what the bound protects.
template <typename Int>
OptionSpec integer(std::string name, char short_name, const char* group, const char* help, Int Options::*member,
                   long long lo, long long hi, const char* why = nullptr) {
    std::string n = name;
    return {std::move(name), short_name, "N", group, help,
            [member, n, lo, hi, why](Options& o, const std::string& v) {
                o.*member = static_cast<Int>(parse_integer(n, v, lo, hi, why));
            },
            [member](const Options& o) { return std::to_string(o.*member); }};
}

OptionSpec real(std::string name, const char* group, const char* help, double Options::*member, double lo, double hi,
                bool lo_open = false) {
    std::string n = name;
    return {std::move(name), 0, "D", group, help,
            [member, n, lo, hi, lo_open](Options& o, const std::string& v) {
                o.*member = parse_real(n, v, lo, hi, lo_open);
            },
            [member](const Options& o) { return format_double(o.*member); }};
}

/// An option whose value is one of a few names, each standing for a value of `member`. The
/// error lists them: "--NAME: expected a, b or c, got 'x'".
template <typename T>
OptionSpec choice(std::string name, const char* value_name, const char* group, const char* help, T Options::*member,
                  std::vector<std::pair<std::string, T>> names) {
    std::string expected;
    for (std::size_t i = 0; i < names.size(); ++i)
        expected += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i].first;
    std::string n = name;
    return {std::move(name), 0, value_name, group, help,
            [member, names, n, expected](Options& o, const std::string& v) {
                for (const auto& [text, value] : names)
                    if (v == text) {
                        o.*member = value;
                        return;
                    }
                throw InputError("--" + n + ": expected " + expected + ", got '" + v + "'");
            },
            [member, names](const Options& o) {
                for (const auto& [text, value] : names)
                    if (o.*member == value) return text;
                return std::string();
            }};
}

OptionSpec resolution(std::string name, const char* help, int size) {
    return {std::move(name), 0, nullptr, "output", help,
            [size](Options& o, const std::string&) { o.resolution_override = size; },
            [size](const Options& o) { return std::string(o.resolution_override == size ? "on" : "off"); }};
}

/// A --quality preset: option tokens chosen from bench/trade's error/time curves (docs/ACCURACY.md).
/// The gather distance returns to its default, 0.15 x unit distance, so it follows the scene's unit.
struct QualityPreset {
    const char* name;
    const char* tokens;
};

constexpr QualityPreset quality_presets[] = {
    {"draft", "--caustic-num-photons 1000000 --caustic-num-neighbours 25 --aa-grid 1 --aa-threshold 0.5 "
              "--shadow-grid 2"},
    {"preview", "--caustic-num-photons 10000000 --caustic-num-neighbours 25 --aa-grid 2 --aa-threshold 0.5 "
                "--shadow-grid 3"},
    {"final", "--caustic-num-photons 30000000 --caustic-num-neighbours 50 --aa-grid 4 --aa-threshold 0.25 "
              "--shadow-grid 6"},
};

/// Expands a preset in place: its tokens are applied where --quality stands, so later options win.
void apply_quality_preset(Options& o, const std::string& name) {
    for (const QualityPreset& preset : quality_presets)
        if (name == preset.name) {
            o.caustic_max_dist = -1.0;
            apply_option_tokens(o, split_option_string(preset.tokens));
            return;
        }
    throw InputError("--quality: expected draft, preview or final, got '" + name + "'");
}

/// The preset whose every value `o` has, or "none".
std::string matching_quality_preset(const Options& o) {
    for (const QualityPreset& preset : quality_presets) {
        Options expanded = o;
        apply_quality_preset(expanded, preset.name);
        if (expanded.caustic_num_photons == o.caustic_num_photons &&
            expanded.caustic_num_neighbours == o.caustic_num_neighbours &&
            expanded.caustic_max_dist == o.caustic_max_dist && expanded.aa_grid == o.aa_grid &&
            expanded.aa_threshold == o.aa_threshold && expanded.shadow_grid == o.shadow_grid)
            return preset.name;
    }
    return "none";
}

/// What the photon stage sees of --gi, --draw-gi-map and --draw-gi-only: one GI map for all three.
std::string gi_wanted_text(const Options& o) { return o.gi_wanted() ? "wanted" : "none"; }

const std::vector<OptionSpec>& option_table() {
    constexpr double huge = 1e30;
    static const std::vector<OptionSpec> table = {
        choice<IntegratorKind>(
            "integrator", "classic|progressive", "transport",
            "classic: the original renderer's rules (docs/CAUSTICS.md, rule by rule); progressive: our photon mapper",
            &Options::integrator, {{"classic", IntegratorKind::classic}, {"progressive", IntegratorKind::progressive}})
            .feeds(stage_photons | stage_image),
        flag("a4", 0, "conventions", "course (CS488 A4) conventions: transforms in call order, unit cube [0,1]^3",
             &Options::a4).feeds(stage_scene),
        flag("timing", 't', "reporting", "print per-stage times", &Options::timing).feeds(stage_none),
        flag("silent", 's', "reporting", "no progress bar or messages, only errors", &Options::silent)
            .feeds(stage_none),
        flag("stats", 'S', "reporting", "print statistics (rays by kind, intersections, stage times)", &Options::stats)
            .feeds(stage_none),
        flag("verbose", 'v', "reporting", "print what is being done", &Options::verbose).feeds(stage_none),
        flag("debug", 'd', "reporting", "print debugging details", &Options::debug).feeds(stage_none),
        OptionSpec{"quality", 0, "draft|preview|final", "sampling",
         "preset of photons, N, max distance, anti-aliasing, shadow grid (docs/ACCURACY.md); later options win",
         apply_quality_preset, matching_quality_preset}.preset_of(stage_photons | stage_image),
        flag("disable-aa", 0, "sampling", "one sample per pixel, no adaptive anti-aliasing", &Options::disable_aa)
            .feeds(stage_image),
        integer("aa-grid", 0, "sampling", "adaptive anti-aliasing: N x N samples in an edge pixel", &Options::aa_grid, 1,
                16).feeds(stage_image),
        real("aa-threshold", "sampling", "colour difference to a neighbour that triggers anti-aliasing",
             &Options::aa_threshold, 0.0, huge).feeds(stage_image),
        flag("draw-aa", 0, "debug views", "show the anti-aliased pixels in red", &Options::draw_aa).feeds(stage_image),
        flag("reproducible", 0, "sampling", "fixed random streams: identical output for any thread count",
             &Options::reproducible).feeds(stage_photons | stage_image),
        OptionSpec{"passes", 0, "N", "sampling",
         "progressive: passes of fresh photons and jittered pixel samples, averaged while the gather radius "
         "shrinks (1 = one k-nearest pass, the default without --time or --target-error; 0 = until --time or "
         "--target-error, the default with either; at most 2^23)",
         [](Options& o, const std::string& v) {
             o.passes = static_cast<int>(parse_integer("passes", v, 0, 8'388'608));
             o.passes_given = true;
         },
         // Only a --passes that was given is told: without it the other rules decide the limit.
         [](const Options& o) { return o.passes_given || o.passes != 1 ? std::to_string(o.passes) : std::string(); }}
            .feeds(stage_image),
        real("time", "sampling", "progressive: start no pass that would end past this many seconds (0 = no limit)",
             &Options::time_limit, 0.0, 1e7).feeds(stage_image),
        real("target-error", "sampling",
             "progressive: stop once the estimated relative error over the caustics is below this (0 = none)",
             &Options::target_error, 0.0, 10.0).feeds(stage_image),
        integer("seed", 0, "sampling", "base of the random streams", &Options::seed, 0,
                std::numeric_limits<long long>::max()).feeds(stage_photons | stage_image),
        integer("threads", 'j', "performance", "worker threads (0 = all cores)", &Options::threads, 0, 1024)
            .feeds(stage_none),
        flag("disable-bv", 0, "performance", "no bounding volumes around analytic primitives: each ray tests them all (for comparison)", &Options::disable_bv)
            .feeds(stage_scene),
        flag("disable-csg-bb", 0, "performance", "no bounding boxes around CSG subtrees (for comparison)",
             &Options::disable_csg_bb).feeds(stage_scene),
        integer("max-depth", 0, "optics", "progressive: recursion limit for reflected and refracted rays (classic: white past depth 15, its deep-ray rule)", &Options::max_depth, 0,
                64).feeds(stage_photons | stage_image),
        real("min-weight", "optics", "progressive: end a ray path when its weight falls below this (classic: its view-ray cut at 0.02 luma)", &Options::min_weight, 0.0, 1.0)
            .feeds(stage_image),
        real("roulette-weight", "optics", "progressive: a ray path whose weight falls below this goes on at random, with probability weight / D, carrying D (the same image on average from fewer rays; 0 = off; classic: unused)", &Options::roulette_weight, 0.0, 1.0)
            .feeds(stage_image),
        flag("no-soft-shadows", 0, "lights", "treat spherical lights as points", &Options::no_soft_shadows)
            .feeds(stage_image),
        OptionSpec{"shadow-grid", 0, "N", "lights", "soft shadows: N x N samples on a spherical light (turns soft shadows on)",
         [](Options& o, const std::string& v) {
             o.shadow_grid = static_cast<int>(parse_integer("shadow-grid", v, 1, 64));
             o.no_soft_shadows = false;
         },
         [](const Options& o) { return std::to_string(o.shadow_grid); }}.feeds(stage_image),
        flag("rays", 0, "output", "orange sunburst background instead of the miss colour", &Options::rays)
            .feeds(stage_image),
        flag("srgb", 0, "output", "encode sRGB in the PNG (default: clamped linear, as the original)",
             &Options::srgb).feeds(stage_output),
        choice<Tonemap>("tonemap", "clamp|reinhard|filmic", "output",
                        "PNG tone curve: clamp (the original's), x/(1+x), ACES fit (docs/OUTPUT.md); "
                        "EXR, PFM stay linear",
                        &Options::tonemap,
                        {{"clamp", Tonemap::clamp}, {"reinhard", Tonemap::reinhard}, {"filmic", Tonemap::filmic}})
            .feeds(stage_output),
        real("exposure", "output", "scale the written image by 2^D (stops; every format, before --tonemap)",
             &Options::exposure, -64.0, 64.0).feeds(stage_output),
        choice<ExrPixel>("exr-pixel", "half|float", "output",
                         "channel type of -o OUT.exr: 16-bit half (11 significant bits) or 32-bit float (exact)",
                         &Options::exr_pixel, {{"half", ExrPixel::half}, {"float", ExrPixel::float32}})
            .feeds(stage_output),
        flag("layers", 0, "output",
             "also write the light split into layers: direct, indirect, caustic, background (they sum to the "
             "image), albedo, normal, in a multilayer -o OUT.exr (docs/OUTPUT.md)",
             &Options::layers).feeds(stage_image),
        resolution("minres", "render at 100 x 100", 100).feeds(stage_image),
        resolution("lores", "render at 256 x 256", 256).feeds(stage_image),
        resolution("midres", "render at 512 x 512", 512).feeds(stage_image),
        resolution("hires", "render at 1024 x 1024", 1024).feeds(stage_image),
        real("script-timeout", "scene", "seconds the scene script may run (0 = no limit)", &Options::script_timeout,
             0.0, 1e7).feeds(stage_none),
        integer("script-memory", 0, "scene",
                "MiB the scene script may use: Lua heap, scene data, meshes and decoded images (0 = no limit)",
                &Options::script_memory_mib, 0, 1 << 20).feeds(stage_none),
        integer("render-memory", 0, "scene",
                "MiB the renderer may build: meshes and their BVH, instances, textures, photon maps "
                "(0 = 60% of this machine's memory)",
                &Options::render_memory_mib, 0, 1 << 30).feeds(stage_none),
        integer("caustic-num-photons", 0, "caustics", "photons shot per light for the caustic map (0 = off)",
                &Options::caustic_num_photons, 0, 100'000'000'000LL).feeds(stage_photons),
        integer("caustic-num-neighbours", 0, "caustics", "photons in each radiance estimate",
                &Options::caustic_num_neighbours, 1, 1'000'000,
                "every render thread keeps a search buffer of N photons (8 bytes each), and an estimate "
                "over more than a million photons is a blur").feeds(stage_image),
        integer("caustic-pm-gran", 0, "caustics", "projection-map resolution (cells per half turn)",
                &Options::caustic_pm_gran, 2, 4096,
                "each light's map holds 2 G^2 cells (one byte and one ray each: 33.5 million at 4096)")
            .feeds(stage_photons),
        real("caustic-max-dist", "caustics", "maximum gather distance (default 0.15 x unit distance)",
             &Options::caustic_max_dist, 0.0, huge, true).feeds(stage_image),
        real("accumulation-radius", "caustics",
             "progressive accumulation: the first gather radius, in pixel footprints where it gathers (shrinking "
             "pass by pass; at most --caustic-max-dist)",
             &Options::accumulation_radius, 1e-3, 1e3).feeds(stage_image),
        real("radius-alpha", "caustics",
             "progressive accumulation: how slowly the gather radius shrinks, r^2 <- r^2 (i + D) / (i + 1) after "
             "pass i; 1 keeps the first radius (the image then converges to that radius's blur: for references)",
             &Options::radius_alpha, 0.05, 1.0).feeds(stage_image),
        choice<ProjectionMapMode>("projection-map", "MODE", "caustics",
                                  "auto|on|off: use light projection maps when shooting photons", &Options::projection_map,
                                  {{"auto", ProjectionMapMode::automatic},
                                   {"on", ProjectionMapMode::on},
                                   {"off", ProjectionMapMode::off}}).feeds(stage_photons),
        choice<bool>("caustic-filter", "none|cone", "caustics",
                     "radiance-estimate filter: the original's disc average, or Jensen's cone",
                     &Options::caustic_cone_filter, {{"none", false}, {"cone", true}}).feeds(stage_image),
        choice<bool>("adaptive-radius", "on|off", "caustics",
                     "progressive: shrink or grow each pixel's gather radius after 8, 32, 128, ... passes so that "
                     "its blur and noise balance (off: one radius sequence for every pixel)",
                     &Options::adaptive_radius, {{"on", true}, {"off", false}}).feeds(stage_image),
        choice<bool>("auto-radius", "on|off", "caustics",
                     "progressive: scale every gather radius by one factor before passes 4, 8, 16, ... so that the "
                     "blur and the noise of the error estimate balance (off: --accumulation-radius as given, shrinking "
                     "by the fixed sequence)",
                     &Options::auto_radius, {{"on", true}, {"off", false}}).feeds(stage_image),
        choice<bool>("photon-split", "on|off", "caustics",
                     "progressive: carry the specular weight at mirrors and glass and follow both the reflected and "
                     "the refracted photon, instead of Russian roulette",
                     &Options::photon_split, {{"on", true}, {"off", false}}).feeds(stage_photons),
        choice<bool>("guided-emission", "on|off", "caustics",
                     "progressive: after the first pass, shoot more photons through the parts of the projection map "
                     "whose photons lit what the image shows below white, fewer through the rest (their energies "
                     "adjusted: the same image on average)",
                     &Options::guided_emission, {{"on", true}, {"off", false}}).feeds(stage_image),
        real("photons-per-pixel", "caustics",
             "progressive: shoot at least enough photon directions a pass that about this many photons per image "
             "pixel are traced, shared by the lights (0: --caustic-num-photons as given)",
             &Options::photons_per_pixel, 0.0, 1e3).feeds(stage_photons),
        choice<bool>("photon-emission", "ld|random", "caustics",
                     "photon directions: low-discrepancy (Hammersley) or random", &Options::photon_random_emission,
                     {{"ld", false}, {"random", true}}).feeds(stage_photons),
        real("unit-distance", "caustics", "scene length unit for photon energies", &Options::unit_distance, 0.0, huge,
             true).feeds(stage_photons | stage_image),
        real("energy-fudge", "caustics", "scale factor on photon energy", &Options::energy_fudge, 0.0, huge)
            .feeds(stage_photons),
        flag("draw-caustic-map", 0, "debug views", "show the stored caustic photons as dots",
             &Options::draw_caustic_map).feeds(stage_image),
        flag("draw-caustic-prm", 0, "debug views",
             "accepted for the original's scenes, which set it: renders exactly as without it",
             &Options::draw_caustic_prm).feeds(stage_none),
        flag("show-projection-map", 0, "debug views",
             "tint the surfaces that the lights' projection maps aim photons at (the preview's overlay in batch)",
             &Options::show_projection_map).feeds(stage_photons | stage_image),
        flag("draw-caustics-only", 0, "debug views",
             "show only the caustic radiance (progressive: on black, the image docs/ACCURACY.md measures)",
             &Options::draw_caustics_only).feeds(stage_image),
        choice<ShadingLayer>("show-layer", "LAYER", "debug views",
                             "render one layer as the image: image (all of it), direct, indirect, caustic, background, "
                             "albedo or normal (docs/OUTPUT.md, Layers); passes accumulate it as they do the image",
                             &Options::show_layer,
                             {{"image", ShadingLayer::beauty},
                              {"direct", ShadingLayer::direct},
                              {"indirect", ShadingLayer::indirect},
                              {"caustic", ShadingLayer::caustic},
                              {"background", ShadingLayer::background},
                              {"albedo", ShadingLayer::albedo},
                              {"normal", ShadingLayer::normal}})
            .feeds(stage_image),
        flag("no-caustic-map", 0, "caustics", "no caustic photon map at all", &Options::no_caustic_map)
            .feeds(stage_photons | stage_image),
        flag("gi", 0, "global illumination", "global-illumination photon map: replaces the ambient term (classic)",
             &Options::gi).feeds(stage_photons | stage_image, gi_wanted_text),
        integer("gi-num-photons", 0, "global illumination", "photons shot per light for the GI map",
                &Options::gi_num_photons, 0, 100'000'000'000LL).feeds(stage_photons),
        integer("gi-num-neighbours", 0, "global illumination", "photons in each GI estimate",
                &Options::gi_num_neighbours, 1, 1'000'000,
                "every render thread keeps a search buffer of N photons, and an estimate over more than a "
                "million photons is a blur").feeds(stage_image),
        flag("draw-gi-map", 0, "debug views", "show the stored GI photons as dots (turns --gi on)",
             &Options::draw_gi_map).feeds(stage_photons | stage_image, gi_wanted_text),
        flag("draw-gi-only", 0, "debug views", "show only the GI estimate (turns --gi on)", &Options::draw_gi_only)
            .feeds(stage_photons | stage_image, gi_wanted_text),
    };
    return table;
}

const OptionSpec* find_long(std::string_view name) {
    for (const auto& spec : option_table())
        if (spec.long_name == name) return &spec;
    return nullptr;
}

const OptionSpec* find_short(char c) {
    for (const auto& spec : option_table())
        if (spec.short_name == c) return &spec;
    return nullptr;
}

std::string closest_option(std::string_view name) {
    const OptionSpec* best = nullptr;
    int best_distance = std::numeric_limits<int>::max();
    for (const auto& spec : option_table()) {
        int d = edit_distance(name, spec.long_name);
        if (d < best_distance) best_distance = d, best = &spec;
    }
    if (!best || best_distance > std::max<int>(3, static_cast<int>(name.size()) / 2)) return {};
    return "--" + best->long_name;
}

[[noreturn]] void unknown_option(const std::string& token, std::string_view bare) {
    std::string message = "unknown option '" + token + "'";
    std::string suggestion = closest_option(bare);
    if (!suggestion.empty()) message += " (did you mean " + suggestion + "?)";
    throw InputError(message);
}

}  // namespace

double default_render_memory_bytes() {
    const double pages = static_cast<double>(::sysconf(_SC_PHYS_PAGES));
    return 0.6 * pages * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
}

double Options::render_memory_bytes() const {
    return render_memory_mib > 0 ? static_cast<double>(render_memory_mib) * 1048576.0 : default_render_memory_bytes();
}

int edit_distance(std::string_view a, std::string_view b) {
    std::vector<int> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
    for (size_t i = 1; i <= a.size(); ++i) {
        int diagonal = row[0];
        row[0] = static_cast<int>(i);
        for (size_t j = 1; j <= b.size(); ++j) {
            int above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

void apply_option_tokens(Options& options, const std::vector<std::string>& tokens,
                         std::vector<std::string>* positional, std::vector<std::string>* names_set) {
    for (size_t i = 0; i < tokens.size(); ++i) {
        const std::string& token = tokens[i];
        const OptionSpec* spec = nullptr;
        std::string value;
        bool has_inline_value = false;
        if (token.rfind("--", 0) == 0 && token.size() > 2) {
            std::string name = token.substr(2);
            if (auto eq = name.find('='); eq != std::string::npos) {
                value = name.substr(eq + 1);
                name = name.substr(0, eq);
                has_inline_value = true;
            }
            spec = find_long(name);
            if (!spec) unknown_option(token, name);
        } else if (token.size() == 2 && token[0] == '-' && token[1] != '-') {
            spec = find_short(token[1]);
            if (!spec) unknown_option(token, token.substr(1));
        } else if (token.size() > 2 && token[0] == '-' && token[1] != '-' && find_short(token[1])) {
            // "-j2": a short option with its value attached; "-St": short flags bundled.
            spec = find_short(token[1]);
            if (spec->value_name) {
                value = token.substr(2);
                has_inline_value = true;
            } else {
                for (std::size_t k = 1; k < token.size(); ++k) {
                    const OptionSpec* f = find_short(token[k]);
                    if (!f || f->value_name)
                        throw InputError("unknown option '" + token + "': '-" + token[k] +
                                         "' is not a short flag (a short option taking a value goes alone or "
                                         "first, as in -j2)");
                }
                for (std::size_t k = 1; k + 1 < token.size(); ++k) {
                    find_short(token[k])->set(options, "");
                    if (names_set) names_set->push_back(find_short(token[k])->long_name);
                }
                spec = find_short(token.back());
            }
        } else if (token.size() > 2 && token[0] == '-' && token[1] != '-') {
            // Not a scene name either: say so, rather than "one scene at a time" later.
            throw InputError("unknown option '" + token + "'");
        } else {
            if (!positional) throw InputError("unexpected argument '" + token + "' (options start with --)");
            positional->push_back(token);
            continue;
        }
        if (spec->value_name) {
            if (!has_inline_value) {
                if (i + 1 >= tokens.size())
                    throw InputError("--" + spec->long_name + ": expects a value (" + spec->value_name + ")");
                value = tokens[++i];
            }
        } else if (has_inline_value) {
            throw InputError("--" + spec->long_name + ": takes no value");
        }
        spec->set(options, value);
        if (names_set) names_set->push_back(spec->long_name);
    }
}

std::vector<std::string> split_option_string(std::string_view text) {
    std::vector<std::string> tokens;
    std::string current;
    bool in_token = false;
    char quote = 0;
    for (char c : text) {
        if (quote) {
            if (c == quote) quote = 0;
            else current += c;
        } else if (c == '"' || c == '\'') {
            quote = c;
            in_token = true;
        } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            if (in_token) tokens.push_back(current), current.clear(), in_token = false;
        } else {
            current += c;
            in_token = true;
        }
    }
    if (quote) throw InputError("unterminated quote in option string");
    if (in_token) tokens.push_back(current);
    return tokens;
}

std::string options_help() {
    std::ostringstream out;
    std::vector<std::string> groups;
    for (const auto& spec : option_table())
        if (std::find(groups.begin(), groups.end(), spec.group) == groups.end()) groups.push_back(spec.group);
    const Options defaults;
    for (const auto& group : groups) {
        out << "\n" << group << ":\n";
        for (const auto& spec : option_table()) {
            if (spec.group != group) continue;
            std::string names = spec.short_name ? std::string("-") + spec.short_name + ", " : "    ";
            names += "--" + spec.long_name;
            if (spec.value_name) names += std::string(" ") + spec.value_name;
            out << "  " << names;
            for (size_t pad = names.size(); pad < 30; ++pad) out << ' ';
            out << ' ' << spec.help;
            if (spec.value_name) out << " [" << spec.get(defaults) << "]";
            out << '\n';
        }
    }
    return out.str();
}

std::vector<OptionStages> option_stages() {
    std::vector<OptionStages> out;
    for (const auto& spec : option_table())
        out.push_back({spec.long_name, spec.stages, spec.preset, spec.cache_key ? spec.cache_key : spec.get});
    return out;
}

std::uint64_t hash_options_feeding(std::uint64_t h, const Options& options, unsigned stage) {
    std::string text;
    for (const auto& spec : option_table())
        if (!spec.preset && (spec.stages & stage)) {
            const bool cache_stage = (stage & (stage_image | stage_output)) == 0;
            const auto& value = cache_stage && spec.cache_key ? spec.cache_key : spec.get;
            text += "--" + spec.long_name + ' ' + value(options) + ' ';
        }
    // splitmix64's finaliser over the running hash and the text's hash.
    std::uint64_t x = h ^ (std::hash<std::string>{}(text) + 0x9e3779b97f4a7c15ULL);
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

void check_render_stop_rules(const Options& options) {
    if (options.integrator == IntegratorKind::progressive && options.passes == 0 && options.time_limit <= 0.0 &&
        options.target_error <= 0.0)
        throw InputError("--passes 0 renders until another rule stops it: give --time or --target-error too");
}

void check_shown_layer(const Options& o) {
    if (o.show_layer != ShadingLayer::beauty && o.debug_view())
        throw InputError("--show-layer: a debug view (--draw-aa, --draw-caustic-map, --show-projection-map, "
                         "--draw-caustics-only, --draw-gi-map, --draw-gi-only) replaces the shading the layer is "
                         "part of: drop one of them");
}

std::string describe_non_default(const Options& options) {
    const Options defaults;
    std::string text;
    for (const auto& spec : option_table()) {
        std::string value = spec.get(options);
        if (value == spec.get(defaults)) continue;
        if (!text.empty()) text += ' ';
        text += "--" + spec.long_name;
        if (spec.value_name) text += " " + value;
    }
    return text;
}

}  // namespace caustica
