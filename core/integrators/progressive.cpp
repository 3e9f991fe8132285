#include "core/integrators/progressive.h"

#include "core/shading/optics.h"
#include "core/util/radiance_range.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace caustica {
namespace {

float max_component(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

/// Maps a point of the unit square to the unit disc, preserving area and strata (Shirley-Chiu).
glm::vec2 concentric_disc(float u, float v) {
    const float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
    if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
    constexpr float quarter_pi = 0.78539816339744831f;
    if (std::fabs(a) > std::fabs(b)) return a * glm::vec2(std::cos(quarter_pi * b / a), std::sin(quarter_pi * b / a));
    return b * glm::vec2(std::cos(2.0f * quarter_pi - quarter_pi * a / b), std::sin(2.0f * quarter_pi - quarter_pi * a / b));
}

}  // namespace

glm::vec3 ProgressiveIntegrator::trace_camera_ray(const Ray& ray, RandomStream& random, RayCounters& counters) const {
    ++counters.primary;
    return trace(ray, PathState{}, random, counters);
}

void ProgressiveIntegrator::trace_camera_rays8(const Ray* rays, const int* valid, RandomStream* streams,
                                               glm::vec3* out, RayCounters& counters) const {
    trace_packet8(setup_, rays, valid, true, false, out, counters, [&](int i, const SurfaceHit& hit, const float* visibility) {
        PathState path;
        path.known_visibility = visibility;
        return shade(rays[i], hit, path, streams[i], counters);
    });
}

void ProgressiveIntegrator::trace_samples8(const Ray* rays, const int* valid, RandomStream* streams,
                                           const float* radius_scales, glm::vec3* colour, double* photon,
                                           double* photon_inner, RayCounters& counters) const {
    for (int i = 0; i < 8; ++i) photon[i] = photon_inner[i] = 0.0;
    trace_packet8(setup_, rays, valid, true, false, colour, counters, [&](int i, const SurfaceHit& hit, const float* visibility) {
        counters.photon_value = counters.photon_value_inner = 0.0;
        PathState path;
        path.known_visibility = visibility;
        if (radius_scales) path.radius_scale = radius_scales[i];
        const glm::vec3 c = shade(rays[i], hit, path, streams[i], counters);
        photon[i] = counters.photon_value;
        photon_inner[i] = counters.photon_value_inner;
        return c;
    });
}

bool ProgressiveIntegrator::survives(glm::vec3& weight, float& gain, RandomStream& random) const {
    gain = 1.0f;
    const float w = max_component(weight);
    if (!(w >= params_.min_weight)) return false;
    if (w >= params_.roulette_weight) return true;
    // Russian roulette: the branch's expected radiance is unchanged, and a pixel traces the tree's
    // faint branches (the third internal reflection in glass) only now and then.
    const float chance = w / params_.roulette_weight;
    if (random.uniform() >= chance) return false;
    gain = 1.0f / chance;
    weight *= gain;
    return true;
}

float ProgressiveIntegrator::medium_index(int material) const {
    return material < 0 ? 1.0f : setup_.scene->materials()[material].refractive_index;
}

glm::vec3 ProgressiveIntegrator::trace(const Ray& ray, const PathState& path, RandomStream& random,
                            RayCounters& counters) const {
    SurfaceHit hit;
    const bool found = setup_.scene->intersect(ray, hit, setup_.cancel);
    // Light travelling inside a coloured medium is attenuated with the distance.
    glm::vec3 transmittance(1.0f);
    if (const int medium = path.media.top(); medium >= 0) {
        const Material& m = setup_.scene->materials()[medium];
        transmittance = medium_transmittance(m.medium_colour, found ? hit.t : ray_infinity, setup_.unit_distance);
    }
    // Saturated (radiance_range.h): the caller multiplies the result by a colour of up to 1e6.
    if (!found) return saturate(transmittance * kept(setup_, ShadingLayer::background, background(ray.direction)));
    return saturate(transmittance * shade(ray, hit, path, random, counters));
}

float ProgressiveIntegrator::light_visibility(const Light& light, const glm::vec3& point, RandomStream& random,
                                   RayCounters& counters) const {
    const float eps = setup_.scene->epsilon();
    const glm::vec3 to_centre = light.position - point;
    const float distance = glm::length(to_centre);
    if (light.radius <= 0.0f || !setup_.soft_shadows || distance <= light.radius) {
        ++counters.shadow;
        const Ray shadow{point, to_centre / distance, eps, distance - eps};
        return setup_.scene->occluded(shadow, setup_.cancel) ? 0.0f : 1.0f;
    }
    // Stratified samples over the light's disc as seen from the point.
    const glm::vec3 w = to_centre / distance;
    const glm::vec3 helper = std::fabs(w.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 u = glm::normalize(glm::cross(helper, w)), v = glm::cross(w, u);
    const int n = setup_.shadow_grid;
    int visible = 0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const glm::vec2 disc =
                concentric_disc((static_cast<float>(i) + random.uniform()) / static_cast<float>(n),
                                (static_cast<float>(j) + random.uniform()) / static_cast<float>(n));
            const glm::vec3 target = light.position + light.radius * (disc.x * u + disc.y * v);
            const glm::vec3 d = target - point;
            const float length = glm::length(d);
            if (!(length > 0.0f)) {  // the point is the sample itself: nothing in between
                ++visible;
                continue;
            }
            ++counters.shadow;
            visible += !setup_.scene->occluded(Ray{point, d / length, eps, length - eps}, setup_.cancel);
        }
    }
    return static_cast<float>(visible) / static_cast<float>(n * n);
}

glm::vec3 ProgressiveIntegrator::direct_light(const Material& m, const glm::vec3& kd, const glm::vec3& ks_weighted,
                                              const SurfaceHit& hit, const glm::vec3& n, const glm::vec3& to_eye,
                                              const float* known_visibility, RandomStream& random,
                                              RayCounters& counters) const {
    glm::vec3 colour(0.0f);
    for (std::size_t l = 0; l < setup_.lights.size(); ++l) {
        const Light& light = setup_.lights[l];
        glm::vec3 to_light;
        float distance;
        if (!direction_to_light(light, hit.position, to_light, distance) || glm::dot(n, to_light) <= 0.0f) continue;
        if (kd == glm::vec3(0.0f) && ks_weighted == glm::vec3(0.0f)) continue;
        const float known = known_visibility && l < packet_lights ? known_visibility[l] : -1.0f;
        const float visibility = known >= 0.0f ? known : light_visibility(light, hit.position, random, counters);
        colour = saturate(colour + phong_light(light, visibility, hit.position, n, to_eye, kd, ks_weighted,
                                               m.shininess, setup_.unit_distance));
    }
    return colour;
}

glm::vec3 ProgressiveIntegrator::shade(const Ray& ray, const SurfaceHit& hit, const PathState& path, RandomStream& random,
                            RayCounters& counters) const {
    const Material& m = setup_.scene->materials()[hit.material];
    // Shade the side the ray arrives on.
    glm::vec3 n = glm::dot(hit.normal, ray.direction) < 0.0f ? hit.normal : -hit.normal;
    glm::vec3 kd = m.kd;
    if (setup_.textures && !setup_.textures->empty()) {
        kd = setup_.textures->diffuse(hit.material, hit, kd);
        n = setup_.textures->shading_normal(hit.material, hit, n);
    }
    // --layers: the first surface's albedo or normal instead of its light (shade() is reached
    // through trace() only below the camera ray's own hit, and this returns before that).
    if (is_surface_layer(setup_.layer)) return setup_.layer == ShadingLayer::albedo ? kd : n;
    const glm::vec3 to_eye = -ray.direction;
    if (m.transparent) return saturate(dielectric(ray, hit, m, n, kd, path, random, counters));
    glm::vec3 colour = setup_.draw_caustics_only
                           ? glm::vec3(0.0f)
                           : kept(setup_, ShadingLayer::indirect, setup_.ambient * kd) +
                                 kept(setup_, ShadingLayer::direct,
                                      direct_light(m, kd, m.ks, hit, n, to_eye, path.known_visibility, random, counters));
    if ((setup_.caustic_map || params_.caustic_grid) && kd != glm::vec3(0.0f))
        colour += kept(setup_, ShadingLayer::caustic, caustic_radiance(hit, n, kd, path, path.distance + hit.t, counters));
    if (setup_.draw_caustic_map || !setup_.projection_maps.empty())
        colour = debug_overlays(hit, glm::length(hit.position - ray.origin), colour);
    if (m.reflective && path.depth < params_.max_depth) {
        PathState next = path;
        next.depth += 1;
        next.distance = path.distance + hit.t;
        next.known_visibility = nullptr;
        next.weight = path.weight * glm::min(m.ks, glm::vec3(1.0f));
        float gain;
        if (survives(next.weight, gain, random)) {
            ++counters.reflected;
            const Ray reflected{hit.position, glm::reflect(ray.direction, n), setup_.scene->epsilon(), ray_infinity};
            colour += gain * m.ks * trace(reflected, next, random, counters);
        }
    }
    return saturate(colour);
}

glm::vec3 ProgressiveIntegrator::caustic_radiance(const SurfaceHit& hit, const glm::vec3& n, const glm::vec3& kd,
                                                  const PathState& path, float distance,
                                                  RayCounters& counters) const {
    // Every gather also feeds the progressive probes (RayCounters): kd E at the radius and at the
    // inner radius r / sqrt 2, times the path's weight (what the pixel shows of them), and in a
    // progressive pass the radius.
    auto mean = [](const glm::vec3& c) { return (static_cast<double>(c.x) + c.y + c.z) / 3.0; };
    glm::vec3 irradiance(0.0f), inner(0.0f);
    if (params_.caustic_grid) {  // a progressive pass: a radius fixed in pixel footprints, shrunk
        const float radius = std::min(params_.caustic_max_distance, params_.footprint_radius * distance * params_.radius_scale * path.radius_scale);
        if (radius > 0.0f) {
            const GatherTimer timer(counters);
            counters.radius_log_sum += std::log(static_cast<double>(radius));
            ++counters.radius_samples;
            const PhotonGrid::Gather g = params_.caustic_grid->gather(hit.position, n, radius);
            const float area = 3.14159265358979f * radius * radius;
            irradiance = g.sum / area;
            inner = g.inner / (0.5f * area);
        }
    } else {
        const GatherTimer timer(counters);
        thread_local std::vector<Neighbour> scratch;
        if (scratch.size() < static_cast<std::size_t>(params_.caustic_neighbours))
            scratch.resize(static_cast<std::size_t>(params_.caustic_neighbours));
        PhotonMap::Probe probe;
        irradiance = setup_.caustic_map->estimate(hit.position, n, params_.caustic_neighbours,
                                                  params_.caustic_max_distance, params_.caustic_filter,
                                                  scratch.data(), probe);
        inner = probe.inner;
    }
    // Saturated: a disc of tiny radius can make the estimate overflow.
    const glm::vec3 radiance = kd * saturate(irradiance);
    counters.photon_value += mean(path.weight * radiance);
    counters.photon_value_inner += mean(path.weight * kd * saturate(inner));
    return radiance;
}

glm::vec3 ProgressiveIntegrator::debug_overlays(const SurfaceHit& hit, float distance, glm::vec3 colour) const {
    // --show-projection-map: tint the surface green where a light's projection map is occupied.
    for (const auto& [map, light] : setup_.projection_maps) {
        const glm::vec3 d = hit.position - light;
        const float length = glm::length(d);
        if (map && length > 0.0f && map->occupied(d / length)) colour = 0.5f * colour + glm::vec3(0.05f, 0.35f, 0.05f);
    }
    // --draw-caustic-map: a photon within about a pixel of the hit shows as a dot of its colour.
    if (setup_.draw_caustic_map && setup_.caustic_map) {
        const float radius = std::max(setup_.dot_radius_per_distance * distance, 1e-6f);
        Neighbour one;
        if (setup_.caustic_map->tree().nearest(hit.position, 1, radius, &one) == 1) {
            const glm::vec3 power = setup_.caustic_map->photon(one.index).power;
            const float peak = std::max({power.x, power.y, power.z});
            colour = peak > 0.0f ? power / peak : glm::vec3(1.0f);
        }
    }
    return colour;
}

glm::vec3 ProgressiveIntegrator::dielectric(const Ray& ray, const SurfaceHit& hit, const Material& m, const glm::vec3& n,
                                            const glm::vec3& kd, const PathState& path, RandomStream& random,
                                            RayCounters& counters) const {
    const MediumTransition media = medium_transition(hit, ray.direction, path.media);
    const float n1 = medium_index(media.from), n2 = medium_index(media.to);
    const float cos_i = -glm::dot(n, ray.direction);
    const float reflectance = fresnel_reflectance(n1, n2, cos_i);
    // A transparent surface has ambient, diffuse and a highlight weighted by R (glass
    // highlights are dim at normal incidence); air is only an interface.
    glm::vec3 colour(0.0f);
    if (!m.air && !setup_.draw_caustics_only)
        colour = kept(setup_, ShadingLayer::indirect, setup_.ambient * kd) +
                 kept(setup_, ShadingLayer::direct, direct_light(m, kd, reflectance * m.ks, hit, n, -ray.direction,
                                                                 path.known_visibility, random, counters));
    if (path.depth >= params_.max_depth) return colour;
    // The medium colour (docs/SCENE_LANGUAGE.md): the reflected ray carries R ks; the transmitted
    // one (1 - R) and the medium's ks^(d/d_u), applied along the segment by trace(); no
    // per-crossing ks factor.
    const glm::vec3 specular = m.air ? glm::vec3(1.0f) : m.ks;
    const float eps = setup_.scene->epsilon();
    PathState next = path;
    next.depth += 1;
    next.distance = path.distance + hit.t;
    next.known_visibility = nullptr;
    float gain;
    if (reflectance > 0.0f) {
        next.weight = path.weight * glm::min(specular, glm::vec3(1.0f)) * reflectance;
        if (survives(next.weight, gain, random)) {
            ++counters.reflected;
            const Ray reflected{hit.position, glm::reflect(ray.direction, n), eps, ray_infinity};
            colour += gain * specular * reflectance * trace(reflected, next, random, counters);
        }
    }
    glm::vec3 direction;
    if (reflectance < 1.0f && refract_direction(ray.direction, n, n1, n2, direction)) {
        next.weight = path.weight * (1.0f - reflectance);
        next.media = media.after;
        if (survives(next.weight, gain, random)) {
            ++counters.refracted;
            const Ray refracted{hit.position, direction, eps, ray_infinity};
            colour += gain * (1.0f - reflectance) * trace(refracted, next, random, counters);
        }
    }
    return colour;
}

}  // namespace caustica
