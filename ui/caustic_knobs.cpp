#include "ui/caustic_knobs.h"

#include "core/integrators/registry.h"

#include <charconv>
#include <string>

namespace caustica::ui {
namespace {

constexpr std::uint32_t bit(KnobField f) { return static_cast<std::uint32_t>(f); }
constexpr std::uint32_t photons = bit(KnobField::photons), unit = bit(KnobField::unit),
                        neighbours = bit(KnobField::neighbours), max_dist = bit(KnobField::max_dist),
                        fudge = bit(KnobField::fudge), map_mode = bit(KnobField::map_mode),
                        granularity = bit(KnobField::granularity), only = bit(KnobField::only),
                        dots = bit(KnobField::dots), integrator = bit(KnobField::integrator), gi = bit(KnobField::gi),
                        gi_photons = bit(KnobField::gi_photons), gi_neighbours = bit(KnobField::gi_neighbours), layer = bit(KnobField::layer),
                        first_radius = bit(KnobField::first_radius), adaptive_radius = bit(KnobField::adaptive_radius),
                        auto_radius = bit(KnobField::auto_radius),
                        guided_emission = bit(KnobField::guided_emission),
                        photons_per_pixel = bit(KnobField::photons_per_pixel), photon_split = bit(KnobField::photon_split),
                        radius_alpha = bit(KnobField::radius_alpha);

const char* map_mode_name(ProjectionMapMode m) {
    return m == ProjectionMapMode::on ? "on" : m == ProjectionMapMode::off ? "off" : "auto";
}

}  // namespace

const char* shown_layer_name(ShadingLayer l) { return l == ShadingLayer::beauty ? "image" : layer_name(l); }

ShadingLayer next_shown_layer(ShadingLayer layer) {
    constexpr std::size_t count = std::size(shown_layers);
    for (std::size_t i = 0; i < count; ++i)
        if (shown_layers[i] == layer) return shown_layers[(i + 1) % count];
    return ShadingLayer::beauty;
}

std::string exact_number(double value) {
    char text[64];
    const auto [end, ec] = std::to_chars(text, text + sizeof text, value);  // shortest round trip
    return ec == std::errc() ? std::string(text, end) : std::to_string(value);
}

const char* knob_label(KnobField field) {
    switch (field) {
    case KnobField::photons: return "photons";
    case KnobField::unit: return "unit distance";
    case KnobField::neighbours: return "neighbours N";
    case KnobField::max_dist: return "max distance";
    case KnobField::fudge: return "energy fudge";
    case KnobField::map_mode: return "projection maps";
    case KnobField::granularity: return "map granularity";
    case KnobField::only: return "photons only";
    case KnobField::dots: return "photon dots";
    case KnobField::integrator: return "integrator";
    case KnobField::gi: return "global illumination";
    case KnobField::gi_photons: return "GI photons";
    case KnobField::gi_neighbours: return "GI neighbours";
    case KnobField::layer: return "show";
    case KnobField::first_radius: return "first radius";
    case KnobField::adaptive_radius: return "radius per pixel";
    case KnobField::auto_radius: return "balanced radius";
    case KnobField::guided_emission: return "guided emission";
    case KnobField::photons_per_pixel: return "photons per pixel";
    case KnobField::photon_split: return "photon splitting";
    case KnobField::radius_alpha: return "radius alpha";
    }
    return "?";
}

std::string knob_value_text(const CausticKnobs& k, KnobField field) {
    switch (field) {
    case KnobField::photons: return std::to_string(k.num_photons);
    case KnobField::unit: return exact_number(k.unit_distance);
    case KnobField::neighbours: return std::to_string(k.num_neighbours);
    case KnobField::max_dist: return k.max_dist < 0.0 ? "auto (" + exact_number(0.15 * k.unit_distance) + ")" : exact_number(k.max_dist);
    case KnobField::fudge: return exact_number(k.energy_fudge);
    case KnobField::map_mode: return map_mode_name(k.projection_map);
    case KnobField::granularity: return std::to_string(k.pm_granularity);
    case KnobField::only: return k.photons_only ? "on" : "off";
    case KnobField::dots: return k.photon_dots ? "on" : "off";
    case KnobField::integrator: return integrator_entry(k.integrator).name;
    case KnobField::gi: return k.gi ? "on" : "off";
    case KnobField::gi_photons: return std::to_string(k.gi_photons);
    case KnobField::gi_neighbours: return std::to_string(k.gi_neighbours);
    case KnobField::layer: return shown_layer_name(k.layer);
    case KnobField::first_radius: return exact_number(k.first_radius);
    case KnobField::adaptive_radius: return k.adaptive_radius ? "on" : "off";
    case KnobField::auto_radius: return k.auto_radius ? "on" : "off";
    case KnobField::guided_emission: return k.guided_emission ? "on" : "off";
    case KnobField::photons_per_pixel: return k.photons_per_pixel == 0.0 ? "0 (off)" : exact_number(k.photons_per_pixel);
    case KnobField::photon_split: return k.photon_split ? "on" : "off";
    case KnobField::radius_alpha: return exact_number(k.radius_alpha);
    }
    return {};
}

bool knob_differs(const CausticKnobs& a, const CausticKnobs& b, KnobField field) {
    return knob_value_text(a, field) != knob_value_text(b, field) ||
           (field == KnobField::max_dist && a.max_dist != b.max_dist);
}

std::vector<std::string> knob_tokens(const CausticKnobs& k, const CausticKnobs& base, KnobField field) {
    if (!knob_differs(k, base, field)) return {};
    switch (field) {
    case KnobField::photons: return {"--caustic-num-photons", std::to_string(k.num_photons)};
    case KnobField::unit: return {"--unit-distance", exact_number(k.unit_distance)};
    case KnobField::neighbours: return {"--caustic-num-neighbours", std::to_string(k.num_neighbours)};
    case KnobField::max_dist:
        // "auto" has no value of its own on the command line; --quality would reset more than it.
        if (k.max_dist < 0.0) return {};
        return {"--caustic-max-dist", exact_number(k.max_dist)};
    case KnobField::fudge: return {"--energy-fudge", exact_number(k.energy_fudge)};
    case KnobField::map_mode: return {"--projection-map", map_mode_name(k.projection_map)};
    case KnobField::granularity: return {"--caustic-pm-gran", std::to_string(k.pm_granularity)};
    case KnobField::only: return k.photons_only ? std::vector<std::string>{"--draw-caustics-only"} : std::vector<std::string>{};
    case KnobField::dots: return k.photon_dots ? std::vector<std::string>{"--draw-caustic-map"} : std::vector<std::string>{};
    case KnobField::integrator: return {"--integrator", knob_value_text(k, field)};
    case KnobField::gi: return k.gi ? std::vector<std::string>{"--gi"} : std::vector<std::string>{};
    case KnobField::gi_photons: return {"--gi-num-photons", std::to_string(k.gi_photons)};
    case KnobField::gi_neighbours: return {"--gi-num-neighbours", std::to_string(k.gi_neighbours)};
    case KnobField::layer: return {"--show-layer", shown_layer_name(k.layer)};
    case KnobField::first_radius: return {"--accumulation-radius", exact_number(k.first_radius)};
    case KnobField::adaptive_radius: return {"--adaptive-radius", k.adaptive_radius ? "on" : "off"};
    case KnobField::auto_radius: return {"--auto-radius", k.auto_radius ? "on" : "off"};
    case KnobField::guided_emission: return {"--guided-emission", k.guided_emission ? "on" : "off"};
    case KnobField::photons_per_pixel: return {"--photons-per-pixel", exact_number(k.photons_per_pixel)};
    case KnobField::photon_split: return {"--photon-split", k.photon_split ? "on" : "off"};
    case KnobField::radius_alpha: return {"--radius-alpha", exact_number(k.radius_alpha)};
    }
    return {};
}

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
    k.layer = o.show_layer;
    k.first_radius = o.accumulation_radius;
    k.adaptive_radius = o.adaptive_radius;
    k.auto_radius = o.auto_radius;
    k.guided_emission = o.guided_emission;
    k.photons_per_pixel = o.photons_per_pixel;
    k.photon_split = o.photon_split;
    k.radius_alpha = o.radius_alpha;
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
    o.show_layer = layer;
    o.accumulation_radius = first_radius;
    o.adaptive_radius = adaptive_radius;
    o.auto_radius = auto_radius;
    o.guided_emission = guided_emission;
    o.photons_per_pixel = photons_per_pixel;
    o.photon_split = photon_split;
    o.radius_alpha = radius_alpha;
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
    if (a.layer != b.layer) mask_ |= layer;
    if (a.first_radius != b.first_radius) mask_ |= first_radius;
    if (a.adaptive_radius != b.adaptive_radius) mask_ |= adaptive_radius;
    if (a.auto_radius != b.auto_radius) mask_ |= auto_radius;
    if (a.guided_emission != b.guided_emission) mask_ |= guided_emission;
    if (a.photons_per_pixel != b.photons_per_pixel) mask_ |= photons_per_pixel;
    if (a.photon_split != b.photon_split) mask_ |= photon_split;
    if (a.radius_alpha != b.radius_alpha) mask_ |= radius_alpha;
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
    if (mask_ & layer) k.layer = person.layer;
    if (mask_ & first_radius) k.first_radius = person.first_radius;
    if (mask_ & adaptive_radius) k.adaptive_radius = person.adaptive_radius;
    if (mask_ & auto_radius) k.auto_radius = person.auto_radius;
    if (mask_ & guided_emission) k.guided_emission = person.guided_emission;
    if (mask_ & photons_per_pixel) k.photons_per_pixel = person.photons_per_pixel;
    if (mask_ & photon_split) k.photon_split = person.photon_split;
    if (mask_ & radius_alpha) k.radius_alpha = person.radius_alpha;
    return k;
}

}  // namespace caustica::ui
