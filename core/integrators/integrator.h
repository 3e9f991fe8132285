// The Whitted-style integrator with the course's Phong model (ambient kd, per light
// kd (n.l) + ks (r.v)^shininess over c0 + c1 d + c2 d^2), shadows (hard, or soft from spherical
// lights), mirror reflection, and Fresnel-weighted reflection/refraction through coloured media.
#pragma once

#include "core/shading/material.h"
#include "core/shading/medium_stack.h"
#include "core/scene/options.h"
#include "core/photons/photon_map.h"
#include "core/photons/projection_map.h"
#include "core/render/random.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_stats.h"
#include "core/shading/texture.h"

#include <vector>

namespace caustica {

/// Scene-wide shading inputs for one render job.
struct ShadingSetup {
    const RenderScene* scene = nullptr;
    const TextureSet* textures = nullptr;  ///< may be null: no textures
    std::vector<Light> lights;
    glm::vec3 ambient{0.0f};
    glm::vec3 miss_colour{0.0f};
    bool sky = false;        ///< --rays
    int max_depth = 8;
    float min_weight = 1e-3f;
    int shadow_grid = 4;     ///< N x N shadow samples on a spherical light
    bool soft_shadows = true;
    float unit_distance = 1.0f;
    // Caustics (seed 1.1.3): the photon map and how it is gathered; null map = no caustics.
    const PhotonMap* caustic_map = nullptr;
    int caustic_neighbours = 100;
    float caustic_max_distance = 0.15f;
    PhotonFilter caustic_filter = PhotonFilter::none;
    bool draw_caustics_only = false;  ///< only the caustic radiance, no ambient or direct light
    bool draw_caustic_map = false;    ///< photons as dots
    float dot_radius_per_distance = 0.0f;  ///< a dot's radius per unit of ray distance (about a pixel)
    /// --draw-caustic-prm: per light, the projection map (null when not built) and its position.
    std::vector<std::pair<const ProjectionMap*, glm::vec3>> projection_maps;
};

/// Radiance along rays; stateless apart from the counters and random stream passed in.
class Integrator {
public:
    explicit Integrator(const ShadingSetup& setup) : setup_(setup) {}

    /// Colour seen along a camera ray.
    glm::vec3 trace_camera_ray(const Ray& ray, RandomStream& random, RayCounters& counters) const;

    /// Lights whose shadow rays primary packets trace together (the rest are traced one by one).
    static constexpr int packet_lights = 8;

    /// Traces, as 8-ray packets, the shadow rays of 8 primary hits towards each point light (up to
    /// packet_lights of them): visibility[lane][light] becomes 0 or 1, or stays -1 where no ray
    /// was needed (no hit, light behind the surface, spherical light).
    void primary_visibility8(const Ray* rays, const SurfaceHit* hits, const bool* found,
                             float (*visibility)[packet_lights], RayCounters& counters) const;

    /// Colour at a surface already found by a primary ray (used by packet tracing), with the
    /// light visibility primary_visibility8 found (or null).
    glm::vec3 shade_primary_hit(const Ray& ray, const SurfaceHit& hit, RandomStream& random, RayCounters& counters,
                                const float* visibility = nullptr) const;

    /// Packet intersection of primary rays against the scene.
    void scene_intersect8(const Ray* rays, const int* valid, SurfaceHit* hits, bool* found) const {
        setup_.scene->intersect8(rays, valid, hits, found);
    }

    /// Colour of a ray that escapes the scene.
    glm::vec3 background(const glm::vec3& direction) const;

    /// Fraction of a light visible from a point (1 or 0 for point lights; stratified for spheres).
    float light_visibility(const Light& light, const glm::vec3& point, RandomStream& random,
                           RayCounters& counters) const;

private:
    /// The state a ray path carries down the recursion.
    struct PathState {
        int depth = 0;
        /// Throughput deciding the min-weight cut. Each bounce's factor counts at most 1 (ks above
        /// 1 included), so that the weights of the paths alive at a depth sum to at most 1 and
        /// no more than 1 / min_weight of them are traced: ks = 1e6 glass cannot make the
        /// reflection/refraction tree grow as 2^depth.
        glm::vec3 weight{1.0f};
        MediumStack media;
        const float* known_visibility = nullptr;  ///< per light, from packets; primary hits only
    };

    glm::vec3 trace(const Ray& ray, const PathState& path, RandomStream& random, RayCounters& counters) const;
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, const PathState& path, RandomStream& random,
                    RayCounters& counters) const;
    glm::vec3 direct_light(const Material& m, const glm::vec3& kd, const SurfaceHit& hit, const glm::vec3& n,
                           const glm::vec3& to_eye, bool diffuse, const float* known_visibility,
                           RandomStream& random, RayCounters& counters) const;
    glm::vec3 dielectric(const Ray& ray, const SurfaceHit& hit, const Material& m, const glm::vec3& n,
                         const PathState& path, RandomStream& random, RayCounters& counters) const;
    float medium_index(int material) const;
    glm::vec3 caustic_radiance(const SurfaceHit& hit, const glm::vec3& n, const glm::vec3& kd,
                               RayCounters& counters) const;
    glm::vec3 debug_overlays(const SurfaceHit& hit, float distance, glm::vec3 colour) const;

    const ShadingSetup& setup_;
};

}  // namespace caustica
