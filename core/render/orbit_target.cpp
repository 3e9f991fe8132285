#include "core/render/orbit_target.h"

#include "core/render/render_session.h"
#include "core/scene/camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace caustica {
namespace {

constexpr int grid_rays = 24;           // rays across each image axis
constexpr double trimmed_fraction = 0.05;  // left out at each end of each axis

/// The middle of the values between the `trimmed_fraction` and 1 - `trimmed_fraction` quantiles.
double trimmed_middle(std::vector<double>& values) {
    std::sort(values.begin(), values.end());
    const std::size_t last = values.size() - 1;
    const auto at = [&](double q) { return values[static_cast<std::size_t>(std::lround(q * static_cast<double>(last)))]; };
    return 0.5 * (at(trimmed_fraction) + at(1.0 - trimmed_fraction));
}

}  // namespace

double visible_centre_distance(const PickFunction& pick, const CameraDesc& camera, int width, int height) {
    if (width <= 0 || height <= 0) return 0.0;
    const Camera rays(camera, width, height);
    std::array<std::vector<double>, 3> axes;
    for (int j = 0; j < grid_rays; ++j)
        for (int i = 0; i < grid_rays; ++i) {
            const float x = (static_cast<float>(i) + 0.5f) * static_cast<float>(width) / grid_rays;
            const float y = (static_cast<float>(j) + 0.5f) * static_cast<float>(height) / grid_rays;
            glm::vec3 point;
            if (!pick(rays.generate(x, y), point)) continue;
            for (int a = 0; a < 3; ++a) axes[a].push_back(point[a]);
        }
    if (axes[0].empty()) return 0.0;
    const glm::dvec3 centre(trimmed_middle(axes[0]), trimmed_middle(axes[1]), trimmed_middle(axes[2]));
    const double distance = glm::dot(centre - camera.eye, glm::normalize(camera.view));
    return distance > 0.0 && std::isfinite(distance) ? distance : 0.0;
}

double visible_centre_distance(const RenderSession& session, const CameraDesc& camera, int width, int height) {
    return visible_centre_distance([&](const Ray& ray, glm::vec3& point) { return session.pick(ray, point); }, camera,
                                   width, height);
}

}  // namespace caustica
