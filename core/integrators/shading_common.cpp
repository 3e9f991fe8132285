#include "core/integrators/shading_common.h"

#include "core/util/radiance_range.h"

#include <algorithm>
#include <cmath>

namespace caustica {

glm::vec3 sunburst(const glm::vec3& direction, const glm::vec3& right, const glm::vec3& up) {
    constexpr double two_pi = 6.283185307179586;
    const double x = glm::dot(direction, right), y = glm::dot(direction, up);
    const double theta = std::atan2(y, x);
    const long long k = static_cast<long long>(std::floor(theta * 28.0 / two_pi - 0.5));
    return (k < 0 ? -k : k) % 2 == 1 ? glm::vec3(1.0f, 0.56f, 0.0f) : glm::vec3(1.0f, 0.29f, 0.0f);
}

glm::vec3 background_colour(const ShadingSetup& setup, const glm::vec3& direction) {
    return setup.sky ? sunburst(direction, setup.view_right, setup.view_up) : setup.miss_colour;
}

bool direction_to_light(const Light& light, const glm::vec3& position, glm::vec3& direction, float& distance) {
    const glm::vec3 to_light = light.position - position;
    distance = glm::length(to_light);
    if (!(distance > 0.0f)) return false;
    direction = to_light / distance;
    return true;
}

glm::vec3 phong_light(const Light& light, float visibility, const glm::vec3& position, const glm::vec3& n,
                      const glm::vec3& to_eye, const glm::vec3& kd, const glm::vec3& ks_weighted, float shininess,
                      float unit_distance) {
    glm::vec3 l;
    float distance;
    if (visibility <= 0.0f || !direction_to_light(light, position, l, distance)) return glm::vec3(0.0f);
    const float n_dot_l = glm::dot(n, l);
    if (n_dot_l <= 0.0f) return glm::vec3(0.0f);
    glm::vec3 lit = kd;
    if (ks_weighted != glm::vec3(0.0f)) {
        const float r_dot_v = glm::dot(2.0f * n_dot_l * n - l, to_eye);
        if (r_dot_v > 0.0f) lit += ks_weighted * (std::pow(r_dot_v, shininess) * n_dot_l);
    }
    return saturate(visibility * light.colour * lit * (n_dot_l * light.attenuation(distance / unit_distance)));
}

void primary_visibility8(const ShadingSetup& setup, const Ray* rays, const SurfaceHit* hits, const bool* found,
                         bool flip_normals, bool grid1_is_point, float (*visibility)[packet_lights],
                         RayCounters& counters) {
    for (int lane = 0; lane < 8; ++lane)
        for (int l = 0; l < packet_lights; ++l) visibility[lane][l] = -1.0f;
    const float eps = setup.scene->epsilon();
    const int lights = std::min<int>(packet_lights, static_cast<int>(setup.lights.size()));
    for (int l = 0; l < lights; ++l) {
        const Light& light = setup.lights[l];
        if (light.radius > 0.0f && setup.soft_shadows && !(grid1_is_point && setup.shadow_grid <= 1)) continue;  // sampled per hit
        Ray shadow[8];
        int valid[8];
        bool blocked[8];
        int count = 0;
        for (int lane = 0; lane < 8; ++lane) {
            valid[lane] = 0;
            if (!found[lane]) continue;
            const SurfaceHit& hit = hits[lane];
            glm::vec3 direction;
            float distance;
            if (!direction_to_light(light, hit.position, direction, distance)) continue;
            const bool front = glm::dot(hit.normal, rays[lane].direction) < 0.0f;
            const glm::vec3 n = flip_normals && !front ? -hit.normal : hit.normal;
            // A bump map can turn the shading normal towards a light the surface faces away from:
            // only lights behind the geometric side are skipped, and only when flipping.
            if (flip_normals && glm::dot(n, direction) <= 0.0f) continue;
            shadow[lane] = Ray{hit.position, direction, eps, distance - eps};
            valid[lane] = 1;
            ++count;
        }
        if (count == 0) continue;
        setup.scene->occluded8(shadow, valid, blocked, setup.cancel);
        counters.shadow += static_cast<std::uint64_t>(count);
        for (int lane = 0; lane < 8; ++lane)
            if (valid[lane]) visibility[lane][l] = blocked[lane] ? 0.0f : 1.0f;
    }
}

}  // namespace caustica
