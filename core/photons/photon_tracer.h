// The caustic photon pass (docs/CAUSTICS.md, "Photon paths"): photons leave each light with the
// original's energy rule, meet surfaces by Russian roulette, and are stored at their first diffuse
// hit after at least one specular interaction (L S+ D paths), where their path ends.
#pragma once

#include "core/shading/material.h"
#include "core/scene/options.h"
#include "core/photons/photon_map.h"
#include "core/photons/projection_map.h"
#include "core/geometry/render_scene.h"

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace caustica {

/// How photon directions are drawn.
enum class PhotonEmission {
    low_discrepancy,  ///< Hammersley points with a random rotation (the default)
    random,           ///< independent uniform directions
};

/// Inputs of a photon pass.
struct PhotonPassSettings {
    long long photons_per_light = 0;  ///< P: photons over each light's full sphere
    double unit_distance = 1.0;
    double energy_fudge = 1.0;
    ProjectionMapMode projection_map = ProjectionMapMode::automatic;
    int projection_map_granularity = 180;
    PhotonEmission emission = PhotonEmission::low_discrepancy;
    std::uint64_t seed = 0;
    /// With a projection map, the pass's directions continue one low-discrepancy sequence over the
    /// occupied cells: the pass's index in it and the seed of its rotation (fixed for all passes).
    int pass = 0;
    std::uint64_t sequence_seed = 0;
    int max_depth = 8;  ///< specular interactions before a photon is dropped
    /// At mirrors and dielectrics, carry the specular weight instead of playing roulette on it, and
    /// follow both the reflected and the refracted photon (a weak branch still plays roulette).
    bool split = false;
    /// Every path with at least one bounce is stored at each diffuse hit and continues by a
    /// Lambertian bounce (progressive --gi); no projection map. Otherwise caustic paths only.
    bool global_illumination = false;
    /// At least this many photons traced a pass per light: the count is raised to this over the
    /// fraction of directions the light's projection map lets through (0: the count as given).
    double min_traced_per_light = 0.0;
    double memory_budget_bytes = 0.0;  ///< refuse passes whose photons could exceed this (0 = default_render_memory_bytes())
    /// Progressive passes after the first reuse its projection maps: one per light (null = none).
    /// Empty: each light's map is decided and built as usual.
    std::vector<const ProjectionMap*> prebuilt_maps;
    /// Guided emission (docs/CAUSTICS.md, "Guided emission"): per light, a weight for each occupied
    /// cell of its map (in OccupiedCells' order; guided_emission.h). A cell's share of
    /// the directions is multiplied by its weight (the count is kept), its photons' energy divided
    /// by it. Null, or a size that is not the map's cells: every weight 1.
    std::vector<const std::vector<float>*> emission_weights;
    /// Count, per occupied cell of each light's map, the photons traced and stored
    /// (LightPhotonReport::cells): what guided emission learns from.
    bool record_cells = false;
    /// When set, counts the directions considered so far (for progress reports).
    std::atomic<long long>* progress = nullptr;
    /// When set, a buffer the pass's photons are gathered into (its contents are dropped, its
    /// memory kept): a later progressive pass hands back the previous pass's photons, so the
    /// copy does not fault in fresh pages every pass.
    std::vector<Photon>* reuse = nullptr;
};

/// Per occupied cell of a light's projection map (in OccupiedCells' order): the photons traced,
/// and the photons stored. A cell's stored photons follow the previous cell's in the pass's
/// photons, and a light's follow the previous light's.
struct EmissionCells {
    std::vector<std::uint32_t> traced, stored;
};

/// What happened for one light.
struct LightPhotonReport {
    long long candidates = 0;     ///< directions considered (P, raised by min_traced_per_light)
    long long traced = 0;         ///< photons actually traced (inside the projection map)
    long long stored = 0;
    bool projection_map_used = false;
    double occupied_fraction = 1.0;
    double map_seconds = 0.0, shoot_seconds = 0.0;
    std::string warning;          ///< e.g. no quadratic falloff
    EmissionCells cells;          ///< with PhotonPassSettings::record_cells and a projection map
};

/// The photons of all lights, with the projection maps that were built.
struct PhotonPassResult {
    std::vector<Photon> photons;
    std::vector<ProjectionMap> maps;     ///< one per light (empty map when none was built)
    std::vector<LightPhotonReport> lights;
};

/// The original's photon energy rule (docs/CAUSTICS.md, "Photon energy"):
/// E = 4 pi d_u^2 C_light / (f_light P), with f_light the light's quadratic falloff coefficient and
/// P the photons over the whole sphere; `fudge` scales it (--energy-fudge).
glm::vec3 photon_energy(const Light& light, double unit_distance, long long photons, double fudge);

/// Russian roulette at a surface ("Photon paths"): P(diffuse) = mean(kd), P(specular) = mean(ks)
/// for mirrors and dielectrics (0 otherwise, air 1), absorption takes the rest.
struct RouletteOdds {
    float diffuse = 0.0f, specular = 0.0f;
};
RouletteOdds roulette_odds(const Material& m);

/// Bytes a photon map of `photons` stored photons may need at most (photons, tree, build buffers).
double photon_memory_bound(double photons);

/// Throws InputError when `photons` stored photons could not fit in `budget_bytes` (0 =
/// default_render_memory_bytes()). Called before anything is allocated for them. `option` names the
/// option that asked for `requested` photons in the message.
void check_photon_memory(double photons, long long requested, double budget_bytes,
                         const char* option = "--caustic-num-photons");

/// Shoots the caustic photons of every light in parallel. Each photon has its own random stream
/// keyed by (seed, light, photon index), so the result is the same for any thread count.
/// Stops early when `cancel` becomes true (docs/RELIABILITY.md, "Bounded time"): what it returns
/// then, photons and projection maps, is incomplete and to be thrown away. Throws InputError,
/// before shooting, when the photons the maps let through could not fit in memory.
PhotonPassResult shoot_caustic_photons(const RenderScene& scene, const std::vector<Light>& lights,
                                       const PhotonPassSettings& settings, const std::atomic<bool>* cancel);

}  // namespace caustica
