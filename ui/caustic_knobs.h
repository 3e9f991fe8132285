// The caustic parameters the preview tunes live, and which of them the person has changed, so
// that a reloaded script keeps the person's values and takes the script's for the others.
#pragma once

#include "core/scene/options.h"

#include <cstdint>
#include <string>
#include <vector>

namespace caustica::ui {

/// The caustic knobs of Options, under the names the panel shows.
struct CausticKnobs {
    IntegratorKind integrator = IntegratorKind::classic;  ///< integrator
    long long num_photons = 0;       ///< caustic_num_photons (0 = no photon pass)
    double unit_distance = 1.0;      ///< unit_distance
    int num_neighbours = 5;          ///< caustic_num_neighbours (N)
    double max_dist = -1.0;          ///< caustic_max_dist (< 0: 0.15 x unit distance)
    double energy_fudge = 1.0;       ///< energy_fudge
    ProjectionMapMode projection_map = ProjectionMapMode::automatic;
    int pm_granularity = 180;        ///< caustic_pm_gran
    bool photons_only = false;       ///< draw_caustics_only
    bool photon_dots = false;        ///< draw_caustic_map
    bool gi = false;                 ///< gi (classic global illumination)
    long long gi_photons = 1'000'000;  ///< gi_num_photons
    int gi_neighbours = 100;         ///< gi_num_neighbours
    ShadingLayer layer = ShadingLayer::beauty;  ///< show_layer: the layer of the light shown
    double first_radius = 3.0;       ///< accumulation_radius (progressive, pixel footprints)
    bool adaptive_radius = false;    ///< adaptive_radius (progressive: a radius per pixel)
    bool auto_radius = false;        ///< auto_radius (progressive: one factor on every radius)
    bool guided_emission = true;     ///< guided_emission (progressive)
    double photons_per_pixel = 0.0;  ///< photons_per_pixel (progressive; 0 = the photon count as given)
    bool photon_split = false;       ///< photon_split (progressive)
    double radius_alpha = 2.0 / 3.0; ///< radius_alpha (progressive: how slowly the radius shrinks)

    /// The knobs as a job's options set them.
    static CausticKnobs from(const Options& options);
    /// Writes the knobs into `options`.
    void apply(Options& options) const;

    bool operator==(const CausticKnobs&) const = default;
};

/// One knob: its bit in KnobOverrides and how the panel and the command line name it.
enum class KnobField : std::uint32_t {
    photons = 1u << 0,
    unit = 1u << 1,
    neighbours = 1u << 2,
    max_dist = 1u << 3,
    fudge = 1u << 4,
    map_mode = 1u << 5,
    granularity = 1u << 6,
    only = 1u << 7,
    dots = 1u << 8,
    integrator = 1u << 9,
    gi = 1u << 10,
    gi_photons = 1u << 11,
    gi_neighbours = 1u << 12,
    layer = 1u << 13,
    first_radius = 1u << 14,
    adaptive_radius = 1u << 15,
    guided_emission = 1u << 16,
    photons_per_pixel = 1u << 17,
    photon_split = 1u << 18,
    radius_alpha = 1u << 19,
    auto_radius = 1u << 20,
};

/// Every knob field, in the panel's order.
inline constexpr KnobField all_knob_fields[] = {
    KnobField::integrator, KnobField::photons,  KnobField::unit, KnobField::neighbours,  KnobField::max_dist,
    KnobField::fudge,      KnobField::map_mode, KnobField::granularity, KnobField::only, KnobField::dots,
    KnobField::gi,         KnobField::gi_photons, KnobField::gi_neighbours, KnobField::layer,
    KnobField::first_radius, KnobField::radius_alpha, KnobField::auto_radius, KnobField::adaptive_radius,
    KnobField::guided_emission,
    KnobField::photon_split, KnobField::photons_per_pixel,
};

/// The layers the "show" menu offers, in its order, and their --show-layer names ("image" for all).
inline constexpr ShadingLayer shown_layers[] = {ShadingLayer::beauty,  ShadingLayer::direct,     ShadingLayer::indirect,
                                                ShadingLayer::caustic, ShadingLayer::background, ShadingLayer::albedo,
                                                ShadingLayer::normal};
const char* shown_layer_name(ShadingLayer layer);
/// The layer after `layer` in the menu's order (after the last: the image).
ShadingLayer next_shown_layer(ShadingLayer layer);

/// The panel's name of a knob ("photons").
const char* knob_label(KnobField field);
/// The field's value in `knobs` as the panel shows it ("1e+07", "progressive", "on").
std::string knob_value_text(const CausticKnobs& knobs, KnobField field);
/// Whether the field differs between `a` and `b`.
bool knob_differs(const CausticKnobs& a, const CausticKnobs& b, KnobField field);
/// Command-line tokens that set the field to its value in `knobs` over options that have
/// `base`'s value (e.g. {"--caustic-num-photons", "10000"}); empty when no option can (a debug
/// view switched off: the options have no "--no-..." form). Reals are written so that they read
/// back bit-identical.
std::vector<std::string> knob_tokens(const CausticKnobs& knobs, const CausticKnobs& base, KnobField field);

/// A double as the shortest text that reads back as the same double.
std::string exact_number(double value);

/// The knobs the person has set (bit per field), over the script's values.
class KnobOverrides {
public:
    /// Forgets the person's value of one field.
    void clear(KnobField field) { mask_ &= ~static_cast<std::uint32_t>(field); }
    /// Whether the person set this field.
    bool has(KnobField field) const { return (mask_ & static_cast<std::uint32_t>(field)) != 0; }
    bool operator==(const KnobOverrides&) const = default;
    /// Records every field where `edited` differs from `current` as set by the person.
    void record(const CausticKnobs& current, const CausticKnobs& edited);
    /// The script's knobs with the person's values in the fields they set.
    CausticKnobs merge(const CausticKnobs& script, const CausticKnobs& person) const;
    /// Forgets every override (back to the script's values).
    void clear() { mask_ = 0; }
    /// Whether any knob is overridden.
    bool any() const { return mask_ != 0; }

private:
    std::uint32_t mask_ = 0;
};

}  // namespace caustica::ui
