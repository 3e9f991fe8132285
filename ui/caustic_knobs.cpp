#include "ui/caustic_knobs.h"

namespace caustica::ui {
namespace {

enum Field : std::uint32_t {
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
};

}  // namespace

CausticKnobs CausticKnobs::from(const Options& o) {
    CausticKnobs k;
    k.num_photons = o.caustic_num_photons;
    k.unit_distance = o.unit_distance;
    k.num_neighbours = o.caustic_num_neighbours;
    k.max_dist = o.caustic_max_dist;
    k.energy_fudge = o.energy_fudge;
    k.projection_map = o.projection_map;
    k.pm_granularity = o.caustic_pm_gran;
    k.photons_only = o.draw_caustics_only;
    k.photon_dots = o.draw_caustic_map;
    k.integrator = o.integrator;
    k.gi = o.gi;
    k.gi_photons = o.gi_num_photons;
    k.gi_neighbours = o.gi_num_neighbours;
    return k;
}

void CausticKnobs::apply(Options& o) const {
    o.caustic_num_photons = num_photons;
    o.unit_distance = unit_distance;
    o.caustic_num_neighbours = num_neighbours;
    o.caustic_max_dist = max_dist;
    o.energy_fudge = energy_fudge;
    o.projection_map = projection_map;
    o.caustic_pm_gran = pm_granularity;
    o.draw_caustics_only = photons_only;
    o.draw_caustic_map = photon_dots;
    o.integrator = integrator;
    o.gi = gi;
    o.gi_num_photons = gi_photons;
    o.gi_num_neighbours = gi_neighbours;
}

void KnobOverrides::record(const CausticKnobs& a, const CausticKnobs& b) {
    if (a.num_photons != b.num_photons) mask_ |= photons;
    if (a.unit_distance != b.unit_distance) mask_ |= unit;
    if (a.num_neighbours != b.num_neighbours) mask_ |= neighbours;
    if (a.max_dist != b.max_dist) mask_ |= max_dist;
    if (a.energy_fudge != b.energy_fudge) mask_ |= fudge;
    if (a.projection_map != b.projection_map) mask_ |= map_mode;
    if (a.pm_granularity != b.pm_granularity) mask_ |= granularity;
    if (a.photons_only != b.photons_only) mask_ |= only;
    if (a.photon_dots != b.photon_dots) mask_ |= dots;
    if (a.integrator != b.integrator) mask_ |= integrator;
    if (a.gi != b.gi) mask_ |= gi;
    if (a.gi_photons != b.gi_photons) mask_ |= gi_photons;
    if (a.gi_neighbours != b.gi_neighbours) mask_ |= gi_neighbours;
}

CausticKnobs KnobOverrides::merge(const CausticKnobs& script, const CausticKnobs& person) const {
    CausticKnobs k = script;
    if (mask_ & photons) k.num_photons = person.num_photons;
    if (mask_ & unit) k.unit_distance = person.unit_distance;
    if (mask_ & neighbours) k.num_neighbours = person.num_neighbours;
    if (mask_ & max_dist) k.max_dist = person.max_dist;
    if (mask_ & fudge) k.energy_fudge = person.energy_fudge;
    if (mask_ & map_mode) k.projection_map = person.projection_map;
    if (mask_ & granularity) k.pm_granularity = person.pm_granularity;
    if (mask_ & only) k.photons_only = person.photons_only;
    if (mask_ & dots) k.photon_dots = person.photon_dots;
    if (mask_ & integrator) k.integrator = person.integrator;
    if (mask_ & gi) k.gi = person.gi;
    if (mask_ & gi_photons) k.gi_photons = person.gi_photons;
    if (mask_ & gi_neighbours) k.gi_neighbours = person.gi_neighbours;
    return k;
}

}  // namespace caustica::ui
