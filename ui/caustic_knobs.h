// The caustic parameters the preview tunes live, and which of them the person has changed, so
// that a reloaded script keeps the person's values and takes the script's for the others.
#pragma once

#include "core/scene/options.h"

#include <cstdint>

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

    /// The knobs as a job's options set them.
    static CausticKnobs from(const Options& options);
    /// Writes the knobs into `options`.
    void apply(Options& options) const;

    bool operator==(const CausticKnobs&) const = default;
};

/// The knobs the person has set (bit per field), over the script's values.
class KnobOverrides {
public:
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
