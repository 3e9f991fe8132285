// The progressive integrator: our physically motivated transport over the scene language
// (docs/SCENE_LANGUAGE.md). Whitted-style recursion with the course's Phong model, shadows (hard, or
// stratified over spherical lights), mirror reflection, Fresnel-weighted reflection and refraction
// through media of colour ks with a medium stack, and the caustic photon map gathered with a side
// test. Passes make it converge (docs/CAUSTICS.md, "Progressive photon mapping").
#pragma once

#include "core/integrators/integrator.h"
#include "core/integrators/shading_common.h"
#include "core/photons/photon_grid.h"
#include "core/shading/medium_stack.h"

namespace caustica {

/// The progressive integrator's own parameters: its path limits, its single pass's k-nearest
/// estimate, and what a pass of the accumulation gathers with (ProgressiveRender sets those).
struct ProgressiveParams {
    int max_depth = 8;            ///< recursion limit (--max-depth)
    float min_weight = 1e-3f;     ///< path weight cut (--min-weight)
    float roulette_weight = 0.0f; ///< below it a path goes on at random (--roulette-weight; 0 = off)
    int caustic_neighbours = 5;   ///< N of the single pass's estimate
    float caustic_max_distance = 0.15f;
    PhotonFilter caustic_filter = PhotonFilter::none;
    /// A pass of the accumulation: its photons in a hashed grid (null: the k-nearest estimate on
    /// the setup's caustic map). A gather at path length l from the camera (reflections and
    /// refractions unfolded) takes the photons within min(caustic_max_distance, footprint_radius l
    /// radius_scale): a radius fixed in pixel footprints, shrunk pass by pass.
    const PhotonGrid* caustic_grid = nullptr;
    float footprint_radius = 0.0f;
    float radius_scale = 1.0f;

    static ProgressiveParams from(const Options& options) {
        ProgressiveParams p;
        p.max_depth = options.max_depth;
        p.min_weight = static_cast<float>(options.min_weight);
        p.roulette_weight = static_cast<float>(options.roulette_weight);
        p.caustic_neighbours = options.caustic_num_neighbours;
        p.caustic_max_distance = static_cast<float>(options.effective_caustic_max_dist());
        p.caustic_filter = options.caustic_cone_filter ? PhotonFilter::cone : PhotonFilter::none;
        return p;
    }
};

class ProgressiveIntegrator final : public Integrator {
public:
    /// With --draw-caustics-only the image holds the caustic radiance alone: rays that leave the
    /// scene are black, whatever the miss colour (the image docs/ACCURACY.md measures errors on).
    explicit ProgressiveIntegrator(const ShadingSetup& setup, const ProgressiveParams& params = {})
        : setup_(setup), params_(params) {
        if (setup_.draw_caustics_only) {
            setup_.miss_colour = glm::vec3(0.0f);
            setup_.sky = false;
        }
    }

    const char* name() const override { return "progressive"; }
    PixelSampling pixel_sampling() const override { return PixelSampling::adaptive_neighbours; }
    glm::vec3 trace_camera_ray(const Ray& ray, RandomStream& random, RayCounters& counters) const override;
    void trace_camera_rays8(const Ray* rays, const int* valid, RandomStream* streams, glm::vec3* out,
                            RayCounters& counters) const override;

    /// Up to 8 camera samples of a progressive pass as a packet (lanes with valid[i] == 0 are
    /// skipped): their colours, and the photon radiance each gathered at the pass radius and at
    /// radius / sqrt 2 (the probes of the error estimate; 0 for a lane that gathered nothing).
    /// `radius_scales` (or null: all 1) multiplies each lane's gather radius: its pixel's own.
    void trace_samples8(const Ray* rays, const int* valid, RandomStream* streams, const float* radius_scales,
                        glm::vec3* colour, double* photon, double* photon_inner, RayCounters& counters) const;

    /// Colour of a ray that escapes the scene.
    glm::vec3 background(const glm::vec3& direction) const { return background_colour(setup_, direction); }

    /// Fraction of a light visible from a point (1 or 0 for point lights; stratified for spheres).
    float light_visibility(const Light& light, const glm::vec3& point, RandomStream& random,
                           RayCounters& counters) const;

private:
    /// The state a ray path carries down the recursion.
    struct PathState {
        int depth = 0;
        /// Throughput deciding the min-weight cut and the roulette. Each bounce's factor counts at
        /// most 1 (ks above 1 included), so that the weights of the paths alive at a depth sum to
        /// at most 1 on average and no more than 1 / min_weight of them are traced on average:
        /// ks = 1e6 glass cannot make the reflection/refraction tree grow as 2^depth. A path that
        /// survives the roulette carries its weight divided by its chance to survive.
        glm::vec3 weight{1.0f};
        float distance = 0.0f;  ///< path length from the camera to the ray's origin
        float radius_scale = 1.0f;  ///< the pixel's own multiplier of the pass's gather radius
        MediumStack media;
        const float* known_visibility = nullptr;  ///< per light, from packets; primary hits only
    };

    glm::vec3 trace(const Ray& ray, const PathState& path, RandomStream& random, RayCounters& counters) const;
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, const PathState& path, RandomStream& random,
                    RayCounters& counters) const;
    glm::vec3 direct_light(const Material& m, const glm::vec3& kd, const glm::vec3& ks_weighted, const SurfaceHit& hit,
                           const glm::vec3& n, const glm::vec3& to_eye, const float* known_visibility,
                           RandomStream& random, RayCounters& counters) const;
    glm::vec3 dielectric(const Ray& ray, const SurfaceHit& hit, const Material& m, const glm::vec3& n,
                         const glm::vec3& kd, const PathState& path, RandomStream& random,
                         RayCounters& counters) const;
    float medium_index(int material) const;
    /// Whether a branch of weight `weight` (set in it already) is traced: never below min_weight;
    /// below roulette_weight with probability max(weight) / roulette_weight, and then `weight`
    /// and `gain` (what the branch's radiance is multiplied by) are divided by that chance.
    bool survives(glm::vec3& weight, float& gain, RandomStream& random) const;
    /// kd E at a diffuse hit `distance` along `path` from the camera (its weight, its radius scale).
    glm::vec3 caustic_radiance(const SurfaceHit& hit, const glm::vec3& n, const glm::vec3& kd, const PathState& path,
                               float distance, RayCounters& counters) const;
    glm::vec3 debug_overlays(const SurfaceHit& hit, float distance, glm::vec3 colour) const;

    ShadingSetup setup_;
    ProgressiveParams params_;
};

}  // namespace caustica
