// The photon stage of a render session: projection maps, photon shooting and the k-D trees,
// cached by what they depend on (geometry, lights, photon counts, unit distance, fudge, maps,
// integrator). The progressive integrator gets its caustic map (photon_tracer.*); the classic one
// its caustic map and, with --gi, its GI map (classic_photons.*).
#pragma once

#include "core/photons/classic_photons.h"
#include "core/photons/photon_map.h"
#include "core/photons/photon_tracer.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_stats.h"
#include "core/scene/scene_desc.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace caustica {

class Cluster;

/// The lights a job renders with, as the renderer uses them.
std::vector<Light> job_lights(const RenderJob& job);

/// Whether the job wants a map of caustic paths: lights, caustic photons (or the projection-map
/// view) requested, no --no-caustic-map, and a reflective or transparent material on a node.
bool caustic_map_wanted(const RenderJob& job);

/// Whether a classic job needs its photon stage: lights present, and either caustic photons
/// requested, not disabled, with at least one reflective or transparent material on a node (no
/// specular object: no caustics), or the GI map wanted with GI photons requested.
bool classic_photons_wanted(const RenderJob& job);
/// Whether a progressive job needs its photon stage: as classic's caustic map, or with --gi one map
/// of every path with a bounce (lights and GI photons are all it needs).
bool progressive_photons_wanted(const RenderJob& job);

/// Fingerprint of everything the photon maps depend on (not N, the max distance or the camera):
/// with the integrator, and for classic whether the GI map is wanted and its photon count.
std::uint64_t caustic_fingerprint(const RenderJob& job, std::uint64_t geometry_key);

/// The built stage.
struct CausticStage {
    std::uint64_t key = 0;                   ///< caustic_fingerprint it was built for (0 = none)
    std::unique_ptr<PhotonMap> map;          ///< the caustic map; null when the job has no caustics
    std::unique_ptr<PhotonMap> gi_map;       ///< classic GI map; null unless gi_wanted()
    /// A progressive pass's photons in the order they were stored, which the pass loop sorts into
    /// its own grid (`map`, when lookups need it, holds a copy in the k-d tree's order).
    std::vector<Photon> photons;
    /// Whether the progressive pass shot photons (`photons` may still be empty).
    bool photon_pass = false;
    std::vector<ProjectionMap> projection_maps;
    /// Progressive, the first pass: per light what its occupied cells traced and stored (empty
    /// without a map), which guided emission learns from (guided_emission.h).
    std::vector<EmissionCells> emission_cells;
    std::vector<glm::vec3> light_positions;
    std::vector<LightCausticStats> lights;     ///< the caustic pass of each light
    std::vector<LightCausticStats> gi_lights;  ///< the GI pass of each light (classic with GI only)
    std::vector<std::string> warnings;
    double map_seconds = 0.0, shoot_seconds = 0.0, tree_seconds = 0.0;
    std::uint64_t sequence_seed = 0;  ///< progressive: the rotation of the directions' sequence
};

/// The classic integrator's photon stage: its caustic map and, with --gi, its GI map
/// (classic_photons.*). `textures` gives the photons kd(uv); when null and a material has a
/// texture, the stage loads its own. With a `cluster` of several ranks (every rank calls it), each
/// rank shoots its share of the emission blocks and the shares are gathered: every rank then holds
/// the maps one process builds, bit for bit. A failure on any rank throws ClusterError on every
/// rank. `progress` (may be null) counts the directions this rank's cells offer, up to
/// classic_photon_directions(job) alone.
void build_classic_photon_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                                const std::atomic<bool>* cancel, const TextureSet* textures, Cluster* cluster,
                                std::atomic<long long>* progress = nullptr);

/// The photon directions the classic stage of a job considers, both maps and every light that
/// shoots photons (one with quadratic falloff): the total its progress counts up to.
long long classic_photon_directions(const RenderJob& job);

/// The lights of a job that shoot photons (those with quadratic falloff, c2 > 0).
int shooting_lights(const RenderJob& job);

/// What a progressive photon pass's progress counts up to: the count as given (--gi-num-photons
/// with --gi, else --caustic-num-photons; before --photons-per-pixel raises it) for each light
/// that shoots photons.
long long progressive_photon_directions(const RenderJob& job);

/// The photon directions a stage's lights considered (as raised).
long long photon_directions(const CausticStage& stage);

/// What a progressive photon pass adds to the job.
struct PhotonPassExtras {
    std::uint64_t seed = 0;              ///< the pass's photon stream (used when `first` is set)
    const CausticStage* first = nullptr; ///< the first pass: its projection maps are reused
    std::atomic<long long>* progress = nullptr;  ///< counts directions considered
    bool photons_only = false;           ///< build no map: the photons in CausticStage::photons alone
    int pass = 0;                        ///< the pass's place in its group's sequence of directions
    int group = 0;                       ///< its replicate group: each group's directions are their own sequence
    /// Guided emission: per light the weights of its map's occupied cells (null: plain emission).
    const std::vector<std::vector<float>>* emission_weights = nullptr;
    std::vector<Photon>* reuse = nullptr; ///< memory for the photons (PhotonPassSettings::reuse)
};

/// A progressive integrator's photon pass (docs/CAUSTICS.md, "Progressive photon mapping"): with
/// `extras.first`, a fresh photon stream of `extras.seed` through the first pass's projection maps;
/// without, the first pass of the job (its projection maps, photons and, unless
/// `extras.photons_only`, its k-D tree).
void build_progressive_pass(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                            const std::atomic<bool>* cancel, const PhotonPassExtras& extras);

}  // namespace caustica
