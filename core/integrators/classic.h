// The classic integrator: the original renderer's light transport, rule for rule (docs/CAUSTICS.md,
// "The two integrators, rule by rule": the quoted names here are its rules). It is not physically
// consistent and is not meant to be: it exists so that a scene written for the original renders as
// its author saw it. In short:
//   "view-ray cut", "deep rays", "media": view rays weighted by luma, cut below 0.02; depth above
//      15 returns white; reflected and transmitted rays weighted by the ks of the material entered
//      (core/shading/classic_interface.h): the far side of a CSG interface (air outside), a plain
//      object's own on both sides.
//   "soft shadows": a regular N x N shadow grid over a spherical light, no jitter.
//   "anti-aliasing": four corners first (the tile renderer, PixelSampling::corner_grid).
//   "search", "estimate", "GI term": caustic term E (n.v) from the k photons the always-k search
//      returns, gated by > 50 photons and Y(kd) > 0.2; the GI estimate replaces the ambient term.
//   "debug views".
// Photon shooting ("photon emission" to "projection maps") is core/photons/classic_photons.*.
#pragma once

#include "core/integrators/integrator.h"
#include "core/integrators/shading_common.h"

namespace caustica {

/// The classic integrator's own parameters.
struct ClassicParams {
    int caustic_neighbours = 5;             ///< N of the caustic estimate (--caustic-num-neighbours)
    float caustic_prune_distance = 0.15f;   ///< "search": the distance that prunes once N are held
    int gi_neighbours = 100;                ///< N of the GI estimate (--gi-num-neighbours)

    static ClassicParams from(const Options& options) {
        ClassicParams p;
        p.caustic_neighbours = options.caustic_num_neighbours;
        p.caustic_prune_distance = static_cast<float>(options.effective_caustic_max_dist());
        p.gi_neighbours = options.gi_num_neighbours;
        return p;
    }
};

class ClassicIntegrator final : public Integrator {
public:
    /// "deep rays": a ray deeper than this that hits something returns white.
    static constexpr int max_depth = 15;
    /// "view-ray cut": a reflected or transmitted ray is traced only if its luma weight exceeds this.
    static constexpr float min_weight = 0.02f;
    /// "estimate": the caustic term needs more photons than this in the map.
    static constexpr std::size_t min_caustic_photons = 50;
    /// "estimate", "debug views": surfaces with Y(kd) above this receive (show) caustics.
    static constexpr float caustic_luma_gate = 0.2f;
    /// "debug views": the photon dot views show the nearest photon within this many world units.
    static constexpr float dot_radius = 0.01f;

    explicit ClassicIntegrator(const ShadingSetup& setup, const ClassicParams& params = {})
        : setup_(setup), params_(params) {}

    const char* name() const override { return "classic"; }
    PixelSampling pixel_sampling() const override { return PixelSampling::corner_grid; }
    glm::vec3 trace_camera_ray(const Ray& ray, RandomStream& random, RayCounters& counters) const override;
    void trace_camera_rays8(const Ray* rays, const int* valid, RandomStream* streams, glm::vec3* out,
                            RayCounters& counters) const override;

    /// "soft shadows": the fraction of a light visible from a point: one ray to the centre for a
    /// point light (or soft shadows off, or a 1 x 1 grid), else the regular N x N grid of
    /// directions.
    float light_visibility(const Light& light, const glm::vec3& point, RayCounters& counters) const;

    /// "estimate": Sum(power) / (pi r^2) over the photons the always-k search returns (0 for an
    /// empty map).
    glm::vec3 photon_estimate(const PhotonMap& map, const glm::vec3& point, int k, RayCounters& counters) const;

private:
    struct Traced {
        glm::vec3 colour{0.0f};
        float distance = ray_infinity;  ///< to the hit (infinite on a miss)
    };

    Traced trace(const Ray& ray, int depth, float weight, RayCounters& counters) const;
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, int depth, float weight, const float* known_visibility,
                    RayCounters& counters) const;
    /// The local (non-recursive) colour of a surface: the Phong terms with the photon terms, or a
    /// debug view.
    glm::vec3 surface_colour(const Material& m, const SurfaceHit& hit, const glm::vec3& n, const glm::vec3& to_eye,
                             const glm::vec3& kd, const glm::vec3& ks_weighted, const float* known_visibility,
                             RayCounters& counters) const;
    /// The dot views: the nearest photon within dot_radius, normalised to unit length, else black.
    glm::vec3 photon_dot(const PhotonMap* map, const glm::vec3& point) const;

    const ShadingSetup& setup_;
    ClassicParams params_;
};

}  // namespace caustica
