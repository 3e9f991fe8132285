// The Whitted-style integrator with the course's Phong model: ambient kd, per light
// kd (n.l) + ks (r.v)^shininess over c0 + c1 d + c2 d^2, hard shadows, mirror reflection.
#pragma once

#include "core/material.h"
#include "core/options.h"
#include "core/render_scene.h"
#include "core/render_stats.h"

#include <vector>

namespace caustica {

/// Scene-wide shading inputs for one render job.
struct ShadingSetup {
    const RenderScene* scene = nullptr;
    std::vector<Light> lights;
    glm::vec3 ambient{0.0f};
    glm::vec3 miss_colour{0.0f};
    bool sky = false;       ///< --rays
    int max_depth = 8;
    float min_weight = 1e-3f;
};

/// Radiance along rays; stateless apart from the per-thread counters passed in.
class Integrator {
public:
    explicit Integrator(const ShadingSetup& setup) : setup_(setup) {}

    /// Colour seen along a camera ray.
    glm::vec3 trace_camera_ray(const Ray& ray, RayCounters& counters) const;

    /// Colour at a surface already found by a primary ray (used by packet tracing).
    glm::vec3 shade_primary_hit(const Ray& ray, const SurfaceHit& hit, RayCounters& counters) const;

    /// Packet intersection of primary rays against the scene.
    void scene_intersect8(const Ray* rays, const int* valid, SurfaceHit* hits, bool* found) const {
        setup_.scene->intersect8(rays, valid, hits, found);
    }

    /// Colour of a ray that escapes the scene.
    glm::vec3 background(const glm::vec3& direction) const;

private:
    glm::vec3 trace(const Ray& ray, int depth, glm::vec3 weight, RayCounters& counters) const;
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, int depth, glm::vec3 weight,
                    RayCounters& counters) const;

    const ShadingSetup& setup_;
};

}  // namespace caustica
