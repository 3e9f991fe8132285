#include "core/render/render_memory.h"

#include "core/integrators/progressive_accumulator.h"
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/photon_tracer.h"
#include "core/scene/source_location.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

namespace caustica {
namespace {

std::string mebibytes(double bytes) {
    char text[64];
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
    return text;
}

/// A photon map of `per_light` photons (the value of --`option`) for each of `lights` lights,
/// charged to the gr.option call that set the option, else to the gr.render.
MemoryCharge photon_map_charge(const RenderJob& job, const std::string& option, long long per_light, long long lights) {
    MemoryCharge charge;
    charge.bytes = photon_memory_bound(static_cast<double>(per_light) * static_cast<double>(lights));
    if (const SourceLocation* origin = job.option_origin(option)) {
        charge.where = *origin;
        charge.call = "gr.option";
    } else {
        charge.where = job.where;
        charge.call = "gr.render";
    }
    charge.what = "the photon map of --" + option + " " + std::to_string(per_light) + " for " +
                  std::to_string(lights) + (lights == 1 ? " light" : " lights");
    return charge;
}

/// The photon maps no projection map can cut, as the job's integrator builds them: --gi's photons
/// (its own map, or the one map of an integrator without a separate GI map), and the caustic map's
/// with --projection-map off. Only lights with a quadratic falloff get photons.
void charge_photon_maps(const RenderJob& job, std::vector<MemoryCharge>& out) {
    const Options& o = job.options;
    const IntegratorEntry& integrator = integrator_entry(o.integrator);
    if (!integrator.photons_wanted(job)) return;
    long long lit = 0;
    for (int index : job.lights)
        if (static_cast<float>(job.scene->lights.at(static_cast<std::size_t>(index)).falloff.z) > 0.0f) ++lit;
    if (lit == 0) return;
    const bool gi = o.gi_wanted() && o.gi_num_photons > 0;
    if (gi) out.push_back(photon_map_charge(job, "gi-num-photons", o.gi_num_photons, lit));
    const bool caustic_map_of_its_own = !gi || integrator.gi_map;
    if (caustic_map_of_its_own && o.projection_map == ProjectionMapMode::off && o.caustic_num_photons > 0 &&
        caustic_map_wanted(job))
        out.push_back(photon_map_charge(job, "caustic-num-photons", o.caustic_num_photons, lit));
}

/// The image the job renders: the session's float image and the copy its output is written
/// from (12 bytes a pixel each) and, for an accumulation, its per-pixel sums (and a radius per
/// pixel's factors and snapshots, and what its error estimate holds while it runs), and the
/// --layers images, charged to the gr.render.
void charge_image(const RenderJob& job, std::vector<MemoryCharge>& out) {
    const int r = job.options.resolution_override;
    const double width = r ? r : job.width, height = r ? r : job.height;
    double per_pixel = 2.0 * sizeof(glm::vec3);
    if (job.options.accumulates()) {
        per_pixel += ProgressiveAccumulator::sums_per_pixel * sizeof(std::int64_t) +
                     ProgressiveAccumulator::estimate_bytes_per_pixel;
        if (job.options.adaptive_radius)
            per_pixel += sizeof(float) + ProgressiveAccumulator::snapshot_slots * sizeof(std::int64_t);
    }
    // --layers: each layer's image and its scaled copy for the file and, over an accumulation, its
    // double sums.
    if (job.options.layers)
        per_pixel += static_cast<double>(std::size(written_layers)) *
                     (2.0 * sizeof(glm::vec3) + (job.options.accumulates() ? sizeof(glm::dvec3) : 0.0));
    MemoryCharge charge;
    charge.bytes = width * height * per_pixel;
    charge.where = job.where;
    charge.call = "gr.render";
    charge.what = "the " + std::to_string(static_cast<long long>(width)) + " x " +
                  std::to_string(static_cast<long long>(height)) + " image";
    out.push_back(std::move(charge));
}

std::string budget_text(const Options& o) {
    return "the renderer's memory budget of " + mebibytes(o.render_memory_bytes()) +
           (o.render_memory_mib > 0 ? std::string(" (--render-memory MiB raises it)")
                                    : std::string(" (60% of this machine's memory; --render-memory MiB raises it)"));
}

}  // namespace

std::vector<MemoryCharge> render_memory_charges(const RenderJob& job, const FlatScene& flat) {
    std::vector<MemoryCharge> charges = scene_memory_charges(*job.scene, flat);
    charge_photon_maps(job, charges);
    charge_image(job, charges);
    return charges;
}

void check_render_memory(const RenderJob& job, const FlatScene& flat) {
    const std::vector<MemoryCharge> charges = render_memory_charges(job, flat);
    const double needed = total_bytes(charges);
    if (needed <= job.options.render_memory_bytes() || charges.empty()) return;
    const MemoryCharge& largest = *std::max_element(
        charges.begin(), charges.end(), [](const MemoryCharge& a, const MemoryCharge& b) { return a.bytes < b.bytes; });
    const std::string call = largest.call.empty() ? std::string() : largest.call + ": ";
    throw InputError(largest.where, call + largest.what + " would take " + mebibytes(largest.bytes) +
                                        " once built, and the render " + mebibytes(needed) + " in all: more than " +
                                        budget_text(job.options));
}

}  // namespace caustica
