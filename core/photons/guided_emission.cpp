#include "core/photons/guided_emission.h"

#include "core/util/cancel_flag.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

double mean_of(const glm::vec3& v) { return (static_cast<double>(v.x) + v.y + v.z) / 3.0; }

/// The photons of a cell whose worth is measured (docs/CAUSTICS.md, "Guided emission"), and the
/// photons their gathers may scan before the cell stops judging more.
constexpr std::size_t judged_per_cell = 16, scan_budget = 4096;

}  // namespace

std::vector<float> emission_weights(const std::vector<std::uint32_t>& traced, const std::vector<double>& useful) {
    std::vector<float> weights;
    const std::size_t cells = traced.size();
    if (cells == 0 || useful.size() != cells) return weights;
    double traced_sum = 0.0, useful_sum = 0.0;
    for (std::size_t c = 0; c < cells; ++c) {
        traced_sum += traced[c];
        useful_sum += useful[c];
    }
    if (!(traced_sum > 0.0) || !(useful_sum > 0.0) || !std::isfinite(useful_sum)) return weights;
    const double mean_yield = useful_sum / traced_sum;
    // A cell's yield counts this many photons of the light's mean yield besides its own.
    constexpr double prior_photons = 4.0;
    constexpr double lowest = 0.25, highest = 4.0;
    weights.resize(cells);
    for (std::size_t c = 0; c < cells; ++c) {
        const double yield = (useful[c] + prior_photons * mean_yield) / (traced[c] + prior_photons);
        weights[c] = static_cast<float>(std::clamp(std::sqrt(yield / mean_yield), lowest, highest));
    }
    return weights;
}

std::vector<std::vector<float>> learn_emission_weights(const CausticStage& first, const EmissionView& view,
                                                       PhotonGrid& grid, const std::atomic<bool>* cancel) {
    std::vector<std::vector<float>> weights;
    // Each light's photons follow the previous light's; a light without a map (or whose map was
    // not used) has no cells, and its photons, as many as it stored, are skipped.
    const std::size_t lights = first.emission_cells.size();
    if (lights == 0 || first.lights.size() != lights) return weights;
    std::vector<std::size_t> light_start(lights + 1, 0);
    std::size_t in_cells = 0;
    for (std::size_t l = 0; l < lights; ++l) {
        const EmissionCells& cells = first.emission_cells[l];
        if (cells.stored.size() != cells.traced.size()) return weights;
        std::size_t light_photons = 0, light_traced = 0;
        for (std::uint32_t n : cells.stored) light_photons += n;
        for (std::uint32_t n : cells.traced) light_traced += n;
        if (cells.stored.empty()) {
            light_photons = static_cast<std::size_t>(std::max(0LL, first.lights[l].stored));
        } else if (static_cast<long long>(light_photons) != first.lights[l].stored ||
                   static_cast<long long>(light_traced) != first.lights[l].traced) {
            return weights;
        } else {
            in_cells += light_photons;
        }
        light_start[l + 1] = light_start[l] + light_photons;
    }
    // The records must account for every photon of the pass, in order (a cell's photons follow
    // the previous cell's): otherwise they are not this pass's, and nothing is learnt.
    if (in_cells == 0 || light_start[lights] != first.photons.size()) return weights;
    grid.build(first.photons, view.grid_cell);
    constexpr float pi = 3.14159265358979f;
    weights.resize(lights);
    for (std::size_t l = 0; l < lights; ++l) {
        const EmissionCells& cells = first.emission_cells[l];
        if (cells.stored.empty()) continue;
        std::vector<std::size_t> begin(cells.stored.size() + 1, light_start[l]);
        for (std::size_t c = 0; c < cells.stored.size(); ++c) begin[c + 1] = begin[c] + cells.stored[c];
        std::vector<double> useful(cells.stored.size(), 0.0);
        // Each cell's sum in photon order, on whichever thread: the same weights on any count.
        caustica::parallel_for(tbb::blocked_range<std::size_t>(0, cells.stored.size(), 64),
                               [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                if (is_cancelled(cancel)) return;
                // At most judged_per_cell photons of the cell, evenly spaced in its range, stand for
                // all of them, fewer once their gathers have scanned scan_budget photons: a gather
                // where photons crowd (a focus, or wide footprints at low resolutions) finds
                // thousands, and judging every photon there would cost more than a pass.
                const std::size_t stored = begin[c + 1] - begin[c];
                const std::size_t judged = std::min(stored, judged_per_cell);
                double sum = 0.0;
                std::size_t done = 0, scanned = 0;
                for (; done < judged && scanned < scan_budget; ++done) {
                    const Photon& photon = first.photons[begin[c] + done * stored / judged];
                    const float radius = std::min(view.max_radius, view.radius_per_distance * glm::length(photon.position - view.eye));
                    double share = 1.0;
                    if (radius > 0.0f && std::isfinite(radius)) {
                        const PhotonGrid::Gather g = grid.gather(photon.position, -photon.direction, radius);
                        scanned += g.count;
                        const double value = mean_of(g.sum) / (static_cast<double>(pi) * radius * radius);
                        if (value > 1.0) share = 1.0 / value;
                    }
                    sum += share * mean_of(photon.power);
                }
                useful[c] = done > 0 ? sum * static_cast<double>(stored) / static_cast<double>(done) : 0.0;
            }
        });
        if (is_cancelled(cancel)) return {};
        weights[l] = emission_weights(cells.traced, useful);
    }
    return weights;
}

}  // namespace caustica
