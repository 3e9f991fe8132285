// The caustic stage of a render session: projection maps, photon shooting and the k-D tree,
// cached by what they depend on (geometry, lights, photon count, unit distance, fudge, maps).
#pragma once

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

/// The lights a job renders with, as the renderer uses them.
std::vector<Light> job_lights(const RenderJob& job);

/// Whether a job needs the photon pass: photons requested, not disabled, lights present and at
/// least one reflective or transparent material on a node (no specular object: no caustics).
bool caustics_needed(const RenderJob& job);

/// Fingerprint of everything the photon map depends on (not N, the max distance or the camera).
std::uint64_t caustic_fingerprint(const RenderJob& job, std::uint64_t geometry_key);

/// The built stage.
struct CausticStage {
    std::uint64_t key = 0;                   ///< caustic_fingerprint it was built for (0 = none)
    std::unique_ptr<PhotonMap> map;          ///< null when the job has no caustics
    std::vector<ProjectionMap> projection_maps;
    std::vector<glm::vec3> light_positions;
    std::vector<LightCausticStats> lights;
    std::vector<std::string> warnings;
    double map_seconds = 0.0, shoot_seconds = 0.0, tree_seconds = 0.0;
};

/// Builds the stage for a job (maps, photons, tree). Throws InputError for scene errors found
/// on the way (kd + ks > 1 on a specular material, naming the material's line).
void build_caustic_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                         const std::atomic<bool>* cancel);

}  // namespace caustica
