// The classic integrator's photon pass (docs/CAUSTICS.md, "photon emission" to "projection maps"):
// the original renderer's caustic map and global-illumination (GI) map, rule for rule. Photons
// leave each light's centre, one batch per cell of an icosahedral subdivision of the sphere; at
// each hit the luma of kd and ks decides between a diffuse bounce, a specular one and absorption,
// and the power is multiplied by kd or ks without dividing by the probability. The progressive
// integrator's pass is photon_tracer.*.
#pragma once

#include "core/geometry/render_scene.h"
#include "core/photons/photon_map.h"
#include "core/photons/photon_tracer.h"
#include "core/photons/projection_map.h"
#include "core/render/random.h"
#include "core/shading/material.h"
#include "core/scene/options.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace caustica {

class TextureSet;

/// "roulette": a photon makes at most this many hits.
inline constexpr int classic_max_hits = 13;
/// "projection maps": a direction is used when its first hit has a material with Y(ks) above this.
inline constexpr double classic_projection_ks_luma = 0.2;
/// "photon emission": the cells, an icosahedron (20 faces) subdivided 8 times (4 children a level).
inline constexpr int classic_emission_levels = 8;
inline constexpr long long classic_emission_cells = 20LL << (2 * classic_emission_levels);  // 1 310 720

/// Y(c) = 0.299 r + 0.587 g + 0.114 b, in double so that Y(white) is not below any uniform
/// number a RandomStream makes (a white surface always passes the odds it gives).
inline double classic_luma(const glm::vec3& c) {
    return 0.299 * static_cast<double>(c.x) + 0.587 * static_cast<double>(c.y) + 0.114 * static_cast<double>(c.z);
}

/// Which map a photon pass fills.
enum class ClassicMapKind {
    caustic,  ///< stored after a specular choice; only specular choices continue
    gi,       ///< stored after a diffuse choice; every non-absorbing choice continues
};

/// Inputs of the classic photon pass.
struct ClassicPhotonSettings {
    long long caustic_photons = 0;  ///< N of the caustic map (--caustic-num-photons); 0 = no map
    long long gi_photons = 0;       ///< N of the GI map (--gi-num-photons); 0 = no map
    double unit_distance = 1.0;
    double energy_fudge = 1.0;
    ProjectionMapMode projection_map = ProjectionMapMode::automatic;  ///< off disables it, else used
    int projection_map_granularity = 180;
    bool build_projection_maps = false;  ///< build them even without caustic photons (--show-projection-map)
    std::uint64_t seed = 0;
    double memory_budget_bytes = 0.0;  ///< as PhotonPassSettings
    /// Several ranks (docs/SCALING.md): this rank shoots the emission blocks b with
    /// b % share_size == share_rank; merge_classic_photons puts the ranks' photons back in one
    /// process's order.
    int share_rank = 0, share_size = 1;
    /// Counts the directions the cells offer (classic_photons_offered), a block at a time as its
    /// photons are traced, over both maps and every light (null: not counted).
    std::atomic<long long>* progress = nullptr;
};

/// The photons of both maps, the caustic projection maps and what happened per light.
struct ClassicPhotonResult {
    std::vector<Photon> caustic, gi;
    std::vector<ProjectionMap> maps;  ///< one per light (empty when none was built)
    std::vector<LightPhotonReport> caustic_lights, gi_lights;  ///< candidates = photons the cells offer
    /// Photons stored per emission block, light after light (classic_emission_blocks each), for
    /// merging the shares of several ranks.
    std::vector<std::uint32_t> caustic_blocks, gi_blocks;
};

/// Blocks of emission cells the photons are shot in (the unit of a rank's share).
int classic_emission_blocks();

/// One rank's share of the classic photons where it lies (a result in memory, or the bytes another
/// rank sent): its photons as bytes (Photon after Photon) and how many each block stored.
struct ClassicPhotonShare {
    const std::uint8_t* caustic = nullptr;
    std::size_t caustic_count = 0;
    const std::uint8_t* gi = nullptr;
    std::size_t gi_count = 0;
    std::vector<std::uint32_t> caustic_blocks, gi_blocks;
    std::vector<LightPhotonReport> caustic_lights, gi_lights;  ///< counts only
};

/// A view of a result held in memory (it must outlive the view).
ClassicPhotonShare share_of(const ClassicPhotonResult& result);

/// The photons of several ranks' shares (in rank order, each from shoot_classic_photons with
/// share_rank = its index) in the order one process stores them: the same maps, bit for bit.
/// Copies each photon once, blocks in parallel. Sums the lights' counts (no projection maps,
/// timings or warnings: the caller's own). Throws when a share holds fewer photons than its block
/// counts say.
ClassicPhotonResult merge_classic_photons(const std::vector<ClassicPhotonShare>& shares);

/// Photons the cell scheme shoots for N requested: the sum over the 1 310 720 cells of
/// floor(N a_T), a_T the cell's solid angle over 4 pi (7 055 360 at N = 8 000 000). The last few
/// answers are kept: a progress bar asks for the total before the pass asks again.
long long classic_photons_offered(long long requested);

/// The three unit vertices of emission cell `cell` (0 <= cell < classic_emission_cells): its
/// corners on the subdivided flat face, projected on the sphere, computed on the fly. cell =
/// face * 4^8 + the base-4 digits of the child taken at each level, first level first.
void classic_emission_cell(long long cell, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c);

/// Solid angle of the spherical triangle with unit vertices a, b, c.
double spherical_triangle_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

/// "GI map" diffuse direction: at angle alpha from the mirror direction of unit `incoming` about
/// unit `normal` (facing against `incoming`), with sin(alpha) = u1 and azimuth 2 pi u2. The lobe is
/// not clipped: a direction below the surface is returned as it is (the photon goes on into the
/// solid).
glm::vec3 classic_diffuse_direction(const glm::vec3& incoming, const glm::vec3& normal, float u1, float u2);

/// "projection maps" test: a direction is used when its first hit has Y(ks) > 0.2; gr.air() counts
/// (ks = 1), so the openings of cups and tubes are targets.
bool classic_projection_target(const Material& m);

/// Traces one photon of `kind` from `ray` with `power` by the classic photon rules and appends what
/// it stores to `out`. `textures` (may be null) gives kd(uv). Returns the hits it made (at most
/// classic_max_hits, gr.air() surfaces included: they are dielectric interfaces). Once `cancel`
/// (null: none) is set its rays meet nothing: the photon ends at once.
int trace_classic_photon(const RenderScene& scene, const TextureSet* textures, ClassicMapKind kind, Ray ray,
                         glm::vec3 power, RandomStream& random, std::vector<Photon>& out,
                         const std::atomic<bool>* cancel = nullptr);

/// Shoots the caustic and (when settings.gi_photons > 0) GI photons of every light in parallel.
/// A light without quadratic falloff gets none, with a warning (as photon_energy needs c2 > 0).
/// Each photon has its own random stream keyed by (seed, map, light, cell, photon in the cell), so
/// the result is the same for any thread count. Stops early when `cancel` becomes true (docs/
/// RELIABILITY.md, "Bounded time"): what it returns then, photons and projection maps, is
/// incomplete and to be thrown away. Throws InputError, before shooting, when the photons could
/// not fit in memory.
ClassicPhotonResult shoot_classic_photons(const RenderScene& scene, const TextureSet* textures,
                                          const std::vector<Light>& lights, const ClassicPhotonSettings& settings,
                                          const std::atomic<bool>* cancel);

}  // namespace caustica
