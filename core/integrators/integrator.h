// The seam between the image passes and light transport. The tile renderer (core/render/) asks an
// Integrator for the colour along camera rays and how the pixels of an image are sampled; two
// integrators sit behind it, chosen per render by --integrator from the registry (registry.h):
//   classic      the original renderer's rules (docs/CAUSTICS.md), core/integrators/classic.*
//   progressive  our physically motivated photon mapper, core/integrators/progressive.*
// Both share the scene language (docs/SCENE_LANGUAGE.md): core/integrators/shading_common.*.
#pragma once

#include "core/geometry/render_scene.h"
#include "core/integrators/shading_layer.h"
#include "core/photons/photon_map.h"
#include "core/photons/projection_map.h"
#include "core/render/random.h"
#include "core/render/render_stats.h"
#include "core/scene/options.h"
#include "core/shading/material.h"
#include "core/shading/texture.h"

#include <atomic>
#include <memory>
#include <utility>
#include <vector>

namespace caustica {

/// Scene-wide shading inputs for one render job, as every integrator shades them. What only one
/// integrator uses (its depth limits, its gathers' N and distance, its pass's grid and radius) is
/// that integrator's own parameter struct (ClassicParams, ProgressiveParams), made from the job's
/// options by its registry entry.
struct ShadingSetup {
    const RenderScene* scene = nullptr;
    /// The render's cancel flag, passed to every ray query (null: none). Once it is set the
    /// queries answer misses and the colours are meaningless: the tile renderer throws them away.
    const std::atomic<bool>* cancel = nullptr;
    const TextureSet* textures = nullptr;  ///< may be null: no textures
    std::vector<Light> lights;
    glm::vec3 ambient{0.0f};
    glm::vec3 miss_colour{1.0f};  ///< white unless gr.set_miss_colour (docs/SCENE_LANGUAGE.md)
    bool sky = false;             ///< --rays: the orange sunburst behind everything
    glm::vec3 view_right{1.0f, 0.0f, 0.0f}, view_up{0.0f, 1.0f, 0.0f};  ///< camera frame for the sunburst
    int shadow_grid = 4;          ///< N x N shadow samples on a spherical light
    bool soft_shadows = true;
    float unit_distance = 1.0f;
    // Photon maps (null = none).
    const PhotonMap* caustic_map = nullptr;
    const PhotonMap* gi_map = nullptr;  ///< an integrator's own GI map (classic --gi)
    // Debug views (docs/CAUSTICS.md, "debug views").
    bool draw_caustics_only = false;
    bool draw_caustic_map = false;
    bool draw_gi_only = false;
    bool draw_gi_map = false;
    float dot_radius_per_distance = 0.0f;  ///< a pixel footprint's radius per unit of ray distance
    /// --show-projection-map: per light, the projection map (null when not built) and its position.
    std::vector<std::pair<const ProjectionMap*, glm::vec3>> projection_maps;
    /// --layers: the part of the light kept (shading_layer.h); every term is still computed, so a
    /// layer's paths are the image's, random numbers and all.
    ShadingLayer layer = ShadingLayer::beauty;
};

/// How an integrator wants the pixels of an image sampled.
enum class PixelSampling {
    /// A sample through each pixel centre, then an N x N jittered grid where a pixel differs from
    /// a neighbour by more than the threshold.
    adaptive_neighbours,
    /// The classic "anti-aliasing" (docs/CAUSTICS.md): an N x N regular grid; above N = 2 the four
    /// corner samples first, and the rest only where those four differ by more than the threshold.
    corner_grid,
};

/// Radiance along camera rays. Implementations are immutable during a render and called from
/// many threads at once; per-sample state lives in the RandomStream and RayCounters passed in.
class Integrator {
public:
    virtual ~Integrator() = default;

    /// "classic" or "progressive".
    virtual const char* name() const = 0;

    /// How the tile renderer samples pixels for this integrator.
    virtual PixelSampling pixel_sampling() const = 0;

    /// Colour seen along a camera ray.
    virtual glm::vec3 trace_camera_ray(const Ray& ray, RandomStream& random, RayCounters& counters) const = 0;

    /// Colours of up to 8 camera rays (lanes with valid[i] == 0 are skipped); streams[i] belongs
    /// to ray i. The default traces them one by one; integrators override it with packets.
    virtual void trace_camera_rays8(const Ray* rays, const int* valid, RandomStream* streams, glm::vec3* out,
                                    RayCounters& counters) const {
        for (int i = 0; i < 8; ++i)
            if (valid[i]) out[i] = trace_camera_ray(rays[i], streams[i], counters);
    }
};

}  // namespace caustica
