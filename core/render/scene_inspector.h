// The preview's hover readout: what a ray meets first (point, node, material, their script lines)
// and the caustic radiance the job's integrator gathers there. GL-free; RenderSession::inspect
// hands it snapshots of the built scene, its job and the photon stage.
#pragma once

#include "core/geometry/ray.h"
#include "core/scene/options.h"
#include "core/scene/scene_desc.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace caustica {

class RenderScene;
struct CausticStage;

/// What a ray meets first, for the preview's hover readout.
struct SurfaceInspection {
    glm::vec3 point{0.0f};
    float distance = 0.0f;          ///< ray parameter of the hit
    std::string object;             ///< the name of the node whose primitive was hit, printable ("" when not identified)
    std::string object_where;       ///< its script line ("file:line"), printable
    int material = -1;              ///< index into SceneDesc::materials, -1 = the default material
    std::string material_where;     ///< the gr.material call's line
    glm::vec3 kd{0.0f}, ks{0.0f};
    bool reflective = false, transparent = false;
    /// Radiance the caustic photon map adds there, as the integrator gathers it (kd x estimate
    /// for progressive, the classic estimate for classic); empty without a caustic map.
    std::optional<glm::vec3> caustic;
    std::size_t map_photons = 0;    ///< photons in the caustic map used
};

/// Keeps, per built scene, an index of which node made each primitive (made on the first
/// inspection of a scene, so renders that never inspect pay nothing for it). Thread-safe.
class SceneInspector {
public:
    /// What `ray` meets first in `scene` (built from `job`), with the caustic map of `stage` (may
    /// be null) gathered with the N and maximum distance of `options` as its integrator does.
    std::optional<SurfaceInspection> inspect(const std::shared_ptr<const RenderScene>& scene,
                                             const std::shared_ptr<const RenderJob>& job,
                                             const std::shared_ptr<const CausticStage>& stage, const Ray& ray,
                                             const Options& options) const;

private:
    struct Index;  // nodes and materials of a scene's primitives
    static std::shared_ptr<const Index> make_index(const RenderJob& job);
    mutable std::mutex mutex_;  // guards the two below
    mutable std::shared_ptr<const Index> index_;
    mutable std::shared_ptr<const RenderJob> index_job_;  // the job index_ was built for
};

}  // namespace caustica
