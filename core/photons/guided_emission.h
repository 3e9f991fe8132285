// Guided emission (docs/CAUSTICS.md, "Guided emission"): after the first progressive pass, each
// occupied cell of a light's projection map is weighted by how much of what its photons stored
// the camera can still use, and the later passes shoot more photons through the cells that
// weigh more (and fewer, each carrying more energy, through the rest: unbiased).
#pragma once

#include "core/photons/caustic_stage.h"
#include "core/photons/photon_grid.h"

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <vector>

namespace caustica {

/// How the camera gathers photons, for judging what a photon adds: a gather at distance d from the
/// eye has radius min(max_radius, radius_per_distance d); the grid's cells are `grid_cell` wide.
struct EmissionView {
    glm::vec3 eye{0.0f};
    float radius_per_distance = 0.0f, max_radius = 0.0f, grid_cell = 1.0f;
};

/// A light's cell weights from each cell's traced photons and the useful power they stored (in
/// any unit common to the light's cells): the yield useful / traced, shrunk towards the light's
/// mean yield by 4 photons' worth (a cell seen a few times is not judged by them), as
/// sqrt(yield / mean yield) kept within [1/4, 4]. The square root is the allocation that
/// minimises the variance of the useful power for a number of photons traced; the floor keeps
/// every cell sampled. Empty when nothing was traced or nothing useful stored, or the sizes differ.
std::vector<float> emission_weights(const std::vector<std::uint32_t>& traced, const std::vector<double>& useful);

/// Every light's weights from the first pass `first` (its emission_cells, lights and photons, sorted
/// into `grid`, whose contents are replaced). A stored photon's power counts as useful by how far
/// below white the caustic it lands in shows: wholly up to white, 1 / value above it (a pixel
/// already white gains little from more photons). The value is the pass's own estimate there,
/// its photons within the radius the camera gathers with at that distance; at most 16 photons of
/// a cell, evenly spaced among its photons, are judged and stand for the rest (fewer once their
/// gathers have scanned 4096 photons). Empty (plain
/// emission) when the first pass recorded nothing, or once `cancel` is set; a light without a
/// map gets no weights.
std::vector<std::vector<float>> learn_emission_weights(const CausticStage& first, const EmissionView& view,
                                                       PhotonGrid& grid, const std::atomic<bool>* cancel);

}  // namespace caustica
