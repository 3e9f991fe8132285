#include "core/integrators/registry.h"

#include "core/integrators/classic.h"
#include "core/integrators/progressive.h"
#include "core/integrators/progressive_render.h"
#include "core/util/radiance_range.h"

#include <algorithm>

namespace caustica {
namespace {

template <typename T, typename Params>
std::unique_ptr<Integrator> make(const ShadingSetup& setup, const Options& options) {
    return std::make_unique<T>(setup, Params::from(options));
}

// ---- classic: the original renderer's rules (docs/CAUSTICS.md, "The two integrators") ----------

void build_classic_photons(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                           const PhotonStageInputs& in) {
    build_classic_photon_stage(stage, scene, job, in.cancel, in.textures, in.cluster, in.progress);
}

glm::vec3 classic_readout(const PhotonMap& map, const glm::vec3& p, const glm::vec3&, const glm::vec3&,
                          const Options& options, Neighbour* scratch) {
    const int k = std::max(options.caustic_num_neighbours, 1);
    const float prune = static_cast<float>(options.effective_caustic_max_dist());
    return saturate(map.classic_estimate(p, k, prune, scratch).value);
}

// ---- progressive: our consistent photon mapper (docs/CAUSTICS.md, "Progressive photon mapping") -

void build_progressive_photons(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                               const PhotonStageInputs& in) {
    PhotonPassExtras extras;
    extras.progress = in.progress;
    extras.photons_only = !in.lookups;
    build_progressive_pass(stage, scene, job, in.cancel, extras);
}

std::unique_ptr<RenderLoop> progressive_loop() { return std::make_unique<ProgressiveRender>(); }

glm::vec3 progressive_readout(const PhotonMap& map, const glm::vec3& p, const glm::vec3& n, const glm::vec3& kd,
                              const Options& options, Neighbour* scratch) {
    const int k = std::max(options.caustic_num_neighbours, 1);
    const float max_distance = static_cast<float>(options.effective_caustic_max_dist());
    const PhotonFilter filter = options.caustic_cone_filter ? PhotonFilter::cone : PhotonFilter::none;
    return kd * saturate(map.estimate(p, n, k, max_distance, filter, scratch));
}

}  // namespace

const std::vector<IntegratorEntry>& integrator_entries() {
    static const std::vector<IntegratorEntry> entries = {
        {IntegratorKind::classic, "classic", false, true, make<ClassicIntegrator, ClassicParams>, classic_photons_wanted,
         build_classic_photons, classic_photon_directions, nullptr, classic_readout},
        {IntegratorKind::progressive, "progressive", true, false, make<ProgressiveIntegrator, ProgressiveParams>,
         progressive_photons_wanted, build_progressive_photons, progressive_photon_directions, progressive_loop,
         progressive_readout},
    };
    return entries;
}

const IntegratorEntry& integrator_entry(IntegratorKind kind) {
    for (const IntegratorEntry& entry : integrator_entries())
        if (entry.kind == kind) return entry;
    return integrator_entries().front();
}

const IntegratorEntry* find_integrator(std::string_view name) {
    for (const IntegratorEntry& entry : integrator_entries())
        if (name == entry.name) return &entry;
    return nullptr;
}

std::unique_ptr<Integrator> make_integrator(IntegratorKind kind, const ShadingSetup& setup, const Options& options) {
    return integrator_entry(kind).make(setup, options);
}

bool caustics_needed(const RenderJob& job) { return integrator_entry(job.options.integrator).photons_wanted(job); }

void build_caustic_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                         const std::atomic<bool>* cancel, const TextureSet* textures, Cluster* cluster) {
    PhotonStageInputs inputs;
    inputs.cancel = cancel;
    inputs.textures = textures;
    inputs.cluster = cluster;
    integrator_entry(job.options.integrator).build_photons(stage, scene, job, inputs);
}

}  // namespace caustica
