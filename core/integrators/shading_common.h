// The scene language's shading rules that both integrators share (docs/SCENE_LANGUAGE.md, "What a
// scene means"): the luma, the Phong term with falloff in unit distances ("Phong"), the backgrounds
// ("background"), Fresnel reflectance with the media of a hit ("medium colour", "CSG media"), and
// packets of shadow rays for point lights.
#pragma once

#include "core/integrators/integrator.h"
#include "core/util/cancel_flag.h"

namespace caustica {

/// Y(c) = 0.299 r + 0.587 g + 0.114 b: the original's luma wherever a colour becomes a probability
/// or a threshold.
inline float luma(const glm::vec3& c) { return 0.299f * c.x + 0.587f * c.y + 0.114f * c.z; }

/// --rays: 28 alternating orange sectors around the view axis.
glm::vec3 sunburst(const glm::vec3& direction, const glm::vec3& right, const glm::vec3& up);

/// The colour of a ray that leaves the scene: the sunburst under --rays, else the miss colour.
glm::vec3 background_colour(const ShadingSetup& setup, const glm::vec3& direction);

/// `term`, a contribution of kind `kind`, when the setup's layer keeps that kind, else black
/// (--layers; shading_layer.h). The image's own setup keeps every term as it is.
inline glm::vec3 kept(const ShadingSetup& setup, ShadingLayer kind, const glm::vec3& term) {
    return keeps(setup.layer, kind) ? term : glm::vec3(0.0f);
}

/// "Phong", one light: C o [kd + ks' max(r.v, 0)^p (n.l)] (n.l) / (c0 + c1 d + c2 d^2), d in unit
/// distances, where `visibility` is o. Returns 0 when n.l <= 0. `diffuse` off drops kd.
glm::vec3 phong_light(const Light& light, float visibility, const glm::vec3& position, const glm::vec3& n,
                      const glm::vec3& to_eye, const glm::vec3& kd, const glm::vec3& ks_weighted, float shininess,
                      float unit_distance);

/// The unit direction to a light's centre and the distance, or false when the point is on it.
bool direction_to_light(const Light& light, const glm::vec3& position, glm::vec3& direction, float& distance);

/// Packet shadow rays from 8 primary hits to each point light (up to `lights` of them; spherical
/// lights with soft shadows are skipped): visibility[lane][light] becomes 0 or 1, or stays -1
/// where no ray was traced (no hit, or the light behind the surface as `normal_facing` decides).
/// With `flip_normals` the surface side facing the ray is used (progressive); without it the
/// outward normal (classic "normals": not flipped). With `grid1_is_point` a spherical light with a
/// 1 x 1 shadow grid is a point (classic "soft shadows"; docs/CAUSTICS.md).
inline constexpr int packet_lights = 8;
void primary_visibility8(const ShadingSetup& setup, const Ray* rays, const SurfaceHit* hits, const bool* found,
                         bool flip_normals, bool grid1_is_point, float (*visibility)[packet_lights],
                         RayCounters& counters);

/// The packet path of both integrators: intersects up to 8 camera rays, traces their point-light
/// shadow rays as packets (primary_visibility8 with `flip_normals`, `grid1_is_point`), and
/// writes shade(i, hit, visibility) for lanes that hit something, the background for the rest.
/// Once the cancel flag is set the lanes not yet shaded get the background: a lane's shading may
/// gather photons, so a cancelled packet waits for one lane at most (docs/RELIABILITY.md,
/// "Bounded time"); the packet is thrown away.
template <typename Shade>
void trace_packet8(const ShadingSetup& setup, const Ray* rays, const int* valid, bool flip_normals, bool grid1_is_point,
                   glm::vec3* out, RayCounters& counters, Shade&& shade) {
    SurfaceHit hits[8];
    bool found[8];
    setup.scene->intersect8(rays, valid, hits, found, setup.cancel);
    float visibility[8][packet_lights];
    primary_visibility8(setup, rays, hits, found, flip_normals, grid1_is_point, visibility, counters);
    for (int i = 0; i < 8; ++i) {
        if (!valid[i]) continue;
        ++counters.primary;
        const bool shaded = found[i] && !is_cancelled(setup.cancel);
        out[i] = shaded ? shade(i, hits[i], visibility[i])
                        : kept(setup, ShadingLayer::background, background_colour(setup, rays[i].direction));
    }
}

}  // namespace caustica
