#include "core/integrators/classic.h"

#include "core/shading/classic_interface.h"
#include "core/shading/optics.h"
#include "core/util/radiance_range.h"

#include <chrono>
#include <cmath>
#include <vector>

namespace caustica {
namespace {

/// ks^(d/d_u) per channel (docs/CAUSTICS.md, "media"), d the distance to the segment's next hit.
/// A transmitted ray that leaves the scene has no next surface: the original's rule is silent
/// there, and we attenuate nothing rather than turn everything seen through a tinted object black
/// (docs/CAUSTICS.md, "A transmitted segment that leaves the scene").
glm::vec3 segment_transmittance(const glm::vec3& ks, float distance, float unit_distance) {
    return std::isfinite(distance) ? medium_transmittance(ks, distance, unit_distance) : glm::vec3(1.0f);
}

}  // namespace

glm::vec3 ClassicIntegrator::trace_camera_ray(const Ray& ray, RandomStream&, RayCounters& counters) const {
    ++counters.primary;
    return trace(ray, 0, 1.0f, counters).colour;
}

void ClassicIntegrator::trace_camera_rays8(const Ray* rays, const int* valid, RandomStream*, glm::vec3* out,
                                           RayCounters& counters) const {
    trace_packet8(setup_, rays, valid, false, true, out, counters, [&](int i, const SurfaceHit& hit, const float* visibility) {
        return shade(rays[i], hit, 0, 1.0f, visibility, counters);
    });
}

float ClassicIntegrator::light_visibility(const Light& light, const glm::vec3& point, RayCounters& counters) const {
    const float eps = setup_.scene->epsilon();
    glm::vec3 w;
    float distance;
    if (!direction_to_light(light, point, w, distance)) return 1.0f;
    const int n = setup_.shadow_grid;
    if (light.radius <= 0.0f || !setup_.soft_shadows || n <= 1 || distance <= light.radius) {
        ++counters.shadow;
        return setup_.scene->occluded(Ray{point, w, eps, distance - eps}, setup_.cancel) ? 0.0f : 1.0f;
    }
    // "soft shadows": a regular grid of directions over the square [-sin theta, sin theta]^2 around
    // w, no jitter; u is horizontal (w x z), v = w x u.
    glm::vec3 u(w.y, -w.x, 0.0f);
    const float u_length = glm::length(u);
    u = u_length > 0.0f ? u / u_length : glm::vec3(1.0f, 0.0f, 0.0f);  // w along z: any horizontal u
    const glm::vec3 v = glm::cross(w, u);
    const float sin_theta = light.radius / distance;
    int counted = 0, visible = 0;
    for (int i = 0; i < n; ++i) {
        const float du = sin_theta * (-1.0f + (static_cast<float>(i) + 0.5f) * 2.0f / static_cast<float>(n));
        for (int j = 0; j < n; ++j) {
            const float dv = sin_theta * (-1.0f + (static_cast<float>(j) + 0.5f) * 2.0f / static_cast<float>(n));
            const float s = du * du + dv * dv;
            if (!(s < 1.0f)) continue;
            const glm::vec3 direction = du * u + dv * v + std::sqrt(1.0f - s) * w;
            ++counted;
            ++counters.shadow;
            visible += !setup_.scene->occluded(Ray{point, direction, eps, distance - eps}, setup_.cancel);
        }
    }
    return counted > 0 ? static_cast<float>(visible) / static_cast<float>(counted) : 1.0f;
}

glm::vec3 ClassicIntegrator::photon_estimate(const PhotonMap& map, const glm::vec3& point, int k,
                                             RayCounters& counters) const {
    if (map.size() == 0 || k <= 0) return glm::vec3(0.0f);
    thread_local std::vector<Neighbour> scratch;
    if (scratch.size() < static_cast<std::size_t>(k)) scratch.resize(static_cast<std::size_t>(k));
    const GatherTimer timer(counters);
    return saturate(map.classic_estimate(point, k, params_.caustic_prune_distance, scratch.data()).value);
}

glm::vec3 ClassicIntegrator::photon_dot(const PhotonMap* map, const glm::vec3& point) const {
    float distance = 0.0f;
    const Photon* nearest = map ? map->nearest_photon(point, &distance) : nullptr;
    if (!nearest || !(distance < dot_radius)) return glm::vec3(0.0f);
    const float length = glm::length(nearest->power);
    return length > 0.0f ? nearest->power / length : glm::vec3(0.0f);
}

ClassicIntegrator::Traced ClassicIntegrator::trace(const Ray& ray, int depth, float weight,
                                                   RayCounters& counters) const {
    SurfaceHit hit;
    if (!setup_.scene->intersect(ray, hit, setup_.cancel))
        return {kept(setup_, ShadingLayer::background, background_colour(setup_, ray.direction)), ray_infinity};
    if (depth > max_depth)  // "deep rays": trapped light returns white
        return {kept(setup_, ShadingLayer::background, glm::vec3(1.0f)), hit.t};
    return {shade(ray, hit, depth, weight, nullptr, counters), hit.t};
}

glm::vec3 ClassicIntegrator::surface_colour(const Material& m, const SurfaceHit& hit, const glm::vec3& n,
                                            const glm::vec3& to_eye, const glm::vec3& kd,
                                            const glm::vec3& ks_weighted, const float* known_visibility,
                                            RayCounters& counters) const {
    const bool receives = luma(kd) > caustic_luma_gate;
    // The debug views replace the surface's own colour (the recursion still runs).
    if (setup_.draw_caustics_only)
        return receives && setup_.caustic_map ? photon_estimate(*setup_.caustic_map, hit.position,
                                                                params_.caustic_neighbours, counters)
                                              : glm::vec3(0.0f);
    if (setup_.draw_gi_only)
        return receives && setup_.gi_map ? photon_estimate(*setup_.gi_map, hit.position, params_.gi_neighbours, counters)
                                         : glm::vec3(0.0f);
    if (setup_.draw_caustic_map) return luma(kd) < caustic_luma_gate ? glm::vec3(0.0f) : photon_dot(setup_.caustic_map, hit.position);
    if (setup_.draw_gi_map) return luma(kd) < caustic_luma_gate ? glm::vec3(0.0f) : photon_dot(setup_.gi_map, hit.position);
    if (m.air) return glm::vec3(0.0f);  // an empty medium has no surface of its own

    const float n_dot_v = glm::dot(n, to_eye);
    // Ambient, or the GI estimate replaces it ("GI term").
    glm::vec3 colour = kept(setup_, ShadingLayer::indirect,
                            setup_.gi_map ? saturate_signed(kd * photon_estimate(*setup_.gi_map, hit.position,
                                                                                 params_.gi_neighbours, counters) * n_dot_v)
                                          : setup_.ambient * kd);
    for (std::size_t l = 0; l < setup_.lights.size(); ++l) {
        const Light& light = setup_.lights[l];
        glm::vec3 to_light;
        float distance;
        if (!direction_to_light(light, hit.position, to_light, distance) || glm::dot(n, to_light) <= 0.0f) continue;
        const float known = known_visibility && l < static_cast<std::size_t>(packet_lights) ? known_visibility[l] : -1.0f;
        const float o = known >= 0.0f ? known : light_visibility(light, hit.position, counters);
        colour = saturate_signed(colour + kept(setup_, ShadingLayer::direct,
                                               phong_light(light, o, hit.position, n, to_eye, kd, ks_weighted,
                                                           m.shininess, setup_.unit_distance)));
    }
    // "estimate": the caustic term, E (n.v); kd is already in the photons.
    if (setup_.caustic_map && setup_.caustic_map->size() > min_caustic_photons && receives)
        colour = saturate_signed(colour + kept(setup_, ShadingLayer::caustic,
                                               photon_estimate(*setup_.caustic_map, hit.position,
                                                               params_.caustic_neighbours, counters) * n_dot_v));
    // --show-projection-map: tint the surface green where a light's projection map is occupied.
    for (const auto& [map, light] : setup_.projection_maps) {
        const glm::vec3 d = hit.position - light;
        const float length = glm::length(d);
        if (map && length > 0.0f && map->occupied(d / length)) colour = 0.5f * colour + glm::vec3(0.05f, 0.35f, 0.05f);
    }
    return saturate_signed(colour);
}

glm::vec3 ClassicIntegrator::shade(const Ray& ray, const SurfaceHit& hit, int depth, float weight,
                                   const float* known_visibility, RayCounters& counters) const {
    const Material& m = setup_.scene->materials()[hit.material];
    // "normals": the shading normal is the outward one, not turned towards the viewer.
    glm::vec3 n = hit.normal;
    glm::vec3 kd = m.kd;
    if (setup_.textures && !setup_.textures->empty()) {
        kd = setup_.textures->diffuse(hit.material, hit, kd);
        n = setup_.textures->shading_normal(hit.material, hit, n);
    }
    // --layers: the first surface's albedo or normal instead of its light (this is the camera ray's hit).
    if (is_surface_layer(setup_.layer)) return setup_.layer == ShadingLayer::albedo ? kd : n;
    const glm::vec3 to_eye = -ray.direction;
    const float eps = setup_.scene->epsilon();

    if (!m.transparent) {
        glm::vec3 colour = surface_colour(m, hit, n, to_eye, kd, m.ks, known_visibility, counters);
        const float next = weight * luma(glm::min(m.ks, glm::vec3(1.0f)));  // ks > 1 must not lift the cut
        if (m.reflective && next > min_weight) {
            ++counters.reflected;
            const Ray reflected{hit.position, glm::reflect(ray.direction, n), eps, ray_infinity};
            colour = saturate_signed(colour + m.ks * trace(reflected, depth + 1, next, counters).colour);
        }
        return colour;
    }

    // "media": the regions on either side (a CSG surface names them; a plain object is its own
    // material inside and air outside), and the material entered, whose ks weights both the
    // reflected and the transmitted ray: total internal reflection against air costs nothing.
    const auto& materials = setup_.scene->materials();
    const ClassicInterface side = classic_interface(materials, hit, ray.direction);
    const glm::vec3 ks_to = classic_ks(materials, side.entered);
    const float n1 = classic_index(materials, side.near_side), n2 = classic_index(materials, side.far_side);
    const glm::vec3 facing = side.entering ? n : -n;  // refraction needs the side the ray arrives on
    const float reflectance = fresnel_reflectance(n1, n2, glm::dot(facing, to_eye));

    glm::vec3 colour = surface_colour(m, hit, n, to_eye, kd, reflectance * m.ks, known_visibility, counters);
    const glm::vec3 ks_cut = glm::min(ks_to, glm::vec3(1.0f));  // ks > 1 must not lift the cut
    const float reflect_weight = weight * luma(reflectance * ks_cut);
    if (reflect_weight > min_weight) {
        ++counters.reflected;
        const Ray reflected{hit.position, glm::reflect(ray.direction, facing), eps, ray_infinity};
        colour = saturate_signed(colour + reflectance * ks_to *
                                              trace(reflected, depth + 1, reflect_weight, counters).colour);
    }
    const float transmit_weight = weight * luma((1.0f - reflectance) * ks_cut);
    glm::vec3 direction;
    if (transmit_weight > min_weight && reflectance < 0.99f &&
        refract_direction(ray.direction, facing, n1, n2, direction)) {
        ++counters.refracted;
        const Traced through = trace(Ray{hit.position, direction, eps, ray_infinity}, depth + 1, transmit_weight, counters);
        colour = saturate_signed(colour + (1.0f - reflectance) *
                                              segment_transmittance(ks_to, through.distance, setup_.unit_distance) *
                                              through.colour);
    }
    return colour;
}

}  // namespace caustica
