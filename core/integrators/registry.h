// The integrators the renderer knows, each described once: its name, how it is made, the photon
// stage it needs, its own render loop and its hover readout. Nothing outside core/integrators/
// names an integrator or branches on one: the session, the photon stage, the preview and the
// batch command ask this table. docs/ARCHITECTURE.md, "Integrators", says how a third one is added.
#pragma once

#include "core/integrators/integrator.h"
#include "core/photons/caustic_stage.h"
#include "core/render/render_host.h"

#include <atomic>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

namespace caustica {

class Cluster;
class TextureSet;

/// What the photon stage is given besides the scene and the job.
struct PhotonStageInputs {
    const std::atomic<bool>* cancel = nullptr;
    const TextureSet* textures = nullptr;         ///< the session's textures (null: the stage loads its own)
    Cluster* cluster = nullptr;                   ///< the ranks rendering together (null: alone)
    std::atomic<long long>* progress = nullptr;   ///< photon directions considered so far (may be null)
    /// Whether the stage must answer photon lookups (a k-d tree: the single k-nearest pass, the
    /// preview's coarse pass, readouts and photon dots). Accumulated passes gather from their own
    /// grid, so a batch render that accumulates needs none (RenderSession::set_photon_lookups).
    bool lookups = true;
};

struct IntegratorEntry {
    IntegratorKind kind;
    /// The --integrator value, the image metadata's and the preview's name.
    const char* name;
    /// Whether --passes, --time and --target-error make it accumulate passes (Options::accumulates).
    bool accumulates;
    /// Whether --gi builds a GI photon map of its own, gathered with --gi-num-neighbours (else GI
    /// paths go into its one photon map, as the progressive integrator does).
    bool gi_map;
    /// The integrator over a job's shading setup (which must outlive it), with its own parameters
    /// read from the job's options.
    std::unique_ptr<Integrator> (*make)(const ShadingSetup& setup, const Options& options);
    /// Whether a job needs its photon stage at all.
    bool (*photons_wanted)(const RenderJob& job);
    /// Builds the photon stage of a job (the first pass's, for a loop that shoots more).
    void (*build_photons)(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                          const PhotonStageInputs& inputs);
    /// The photon directions the stage considers, for a progress bar (0: it reports none).
    long long (*photon_directions)(const RenderJob& job);
    /// Its render loop for a job that accumulates (null: the session's tile passes).
    std::unique_ptr<RenderLoop> (*make_loop)();
    /// The hover readout: the caustic radiance its gather finds at `p` (normal `n` facing the
    /// viewer, diffuse colour `kd`) with the job's N and distance; `scratch` holds N entries.
    glm::vec3 (*caustic_readout)(const PhotonMap& map, const glm::vec3& p, const glm::vec3& n, const glm::vec3& kd,
                                 const Options& options, Neighbour* scratch);
};

/// Every integrator, the default (classic) first.
const std::vector<IntegratorEntry>& integrator_entries();
/// The entry of `kind`.
const IntegratorEntry& integrator_entry(IntegratorKind kind);
/// The entry named `name`, or null.
const IntegratorEntry* find_integrator(std::string_view name);

/// The integrator `kind` over `setup` (which must outlive it), its parameters from `options`.
std::unique_ptr<Integrator> make_integrator(IntegratorKind kind, const ShadingSetup& setup, const Options& options);

/// Whether a job needs the photon stage of its integrator.
bool caustics_needed(const RenderJob& job);

/// Builds the photon stage of the job's integrator. Throws InputError for scene errors found on the
/// way (progressive: kd + ks > 1 on a specular material, naming the material's line).
void build_caustic_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                         const std::atomic<bool>* cancel, const TextureSet* textures = nullptr,
                         Cluster* cluster = nullptr);

}  // namespace caustica
