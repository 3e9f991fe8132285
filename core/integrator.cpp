#include "core/integrator.h"

#include <algorithm>
#include <cmath>

namespace caustica {

glm::vec3 Integrator::background(const glm::vec3& direction) const {
    if (!setup_.sky) return setup_.miss_colour;
    // A plain daylight sky: deep blue overhead fading to a pale horizon, darker ground below.
    const float up = direction.y;
    if (up < 0.0f) return glm::mix(glm::vec3(0.75f, 0.8f, 0.85f), glm::vec3(0.35f, 0.33f, 0.3f), std::min(1.0f, -up * 4.0f));
    return glm::mix(glm::vec3(0.75f, 0.85f, 1.0f), glm::vec3(0.2f, 0.4f, 0.85f), std::sqrt(up));
}

glm::vec3 Integrator::trace_camera_ray(const Ray& ray, RayCounters& counters) const {
    ++counters.primary;
    return trace(ray, 0, glm::vec3(1.0f), counters);
}

glm::vec3 Integrator::shade_primary_hit(const Ray& ray, const SurfaceHit& hit, RayCounters& counters) const {
    ++counters.primary;
    return shade(ray, hit, 0, glm::vec3(1.0f), counters);
}

glm::vec3 Integrator::trace(const Ray& ray, int depth, glm::vec3 weight, RayCounters& counters) const {
    SurfaceHit hit;
    if (!setup_.scene->intersect(ray, hit)) return background(ray.direction);
    return shade(ray, hit, depth, weight, counters);
}

glm::vec3 Integrator::shade(const Ray& ray, const SurfaceHit& hit, int depth, glm::vec3 weight,
                            RayCounters& counters) const {
    const Material& m = setup_.scene->materials()[hit.material];
    const float eps = setup_.scene->epsilon();
    // Shade the side the ray arrives on.
    const glm::vec3 n = glm::dot(hit.normal, ray.direction) < 0.0f ? hit.normal : -hit.normal;
    const glm::vec3 to_eye = -ray.direction;

    glm::vec3 colour = setup_.ambient * m.kd;
    const bool has_specular = m.ks.x > 0.0f || m.ks.y > 0.0f || m.ks.z > 0.0f;
    for (const Light& light : setup_.lights) {
        glm::vec3 to_light = light.position - hit.position;
        const float distance = glm::length(to_light);
        if (!(distance > eps)) continue;
        to_light /= distance;
        const float n_dot_l = glm::dot(n, to_light);
        if (n_dot_l <= 0.0f) continue;
        ++counters.shadow;
        if (setup_.scene->occluded(Ray{hit.position, to_light, eps, distance - eps})) continue;
        glm::vec3 lit = m.kd * n_dot_l;
        if (has_specular) {
            const glm::vec3 r = glm::reflect(-to_light, n);
            const float r_dot_v = glm::dot(r, to_eye);
            if (r_dot_v > 0.0f) lit += m.ks * std::pow(r_dot_v, m.shininess);
        }
        colour += light.colour * lit * light.attenuation(distance);
    }

    if (m.reflective && depth < setup_.max_depth) {
        const glm::vec3 reflected_weight = weight * m.ks;
        if (std::max({reflected_weight.x, reflected_weight.y, reflected_weight.z}) >= setup_.min_weight) {
            ++counters.reflected;
            const Ray reflected{hit.position, glm::reflect(ray.direction, n), eps, ray_infinity};
            colour += m.ks * trace(reflected, depth + 1, reflected_weight, counters);
        }
    }
    return colour;
}

}  // namespace caustica
