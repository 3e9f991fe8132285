#include "core/photons/photon_map.h"

#include <cmath>

namespace caustica {
namespace {
constexpr float pi = 3.14159265358979323846f;
constexpr float cone_k = 1.1f;
}  // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons) {
    std::vector<glm::vec3> positions(photons.size());
    for (std::size_t i = 0; i < photons.size(); ++i) positions[i] = photons[i].position;
    tree_ = PhotonKdTree(std::move(positions));
    photons_.resize(photons.size());
    for (std::size_t i = 0; i < photons.size(); ++i) photons_[i] = photons[tree_.order()[i]];
}

glm::vec3 PhotonMap::estimate(const glm::vec3& p, const glm::vec3& n, int k, float max_distance,
                              PhotonFilter filter, Neighbour* scratch) const {
    const std::uint32_t found = tree_.nearest(p, static_cast<std::uint32_t>(k), max_distance, scratch);
    if (found == 0) return glm::vec3(0.0f);
    // Radius of the disc holding them: the k-th photon's distance, or the search radius.
    const float radius2 = found == static_cast<std::uint32_t>(k) ? scratch[0].distance2 : max_distance * max_distance;
    if (!(radius2 > 0.0f)) return glm::vec3(0.0f);
    glm::vec3 sum(0.0f);
    if (filter == PhotonFilter::none) {
        for (std::uint32_t i = 0; i < found; ++i) {
            const Photon& photon = photons_[scratch[i].index];
            if (glm::dot(photon.direction, n) < 0.0f) sum += photon.power;
        }
        return sum / (pi * radius2);
    }
    const float radius = std::sqrt(radius2);
    for (std::uint32_t i = 0; i < found; ++i) {
        const Photon& photon = photons_[scratch[i].index];
        if (glm::dot(photon.direction, n) >= 0.0f) continue;
        const float weight = 1.0f - std::sqrt(scratch[i].distance2) / (cone_k * radius);
        if (weight > 0.0f) sum += weight * photon.power;
    }
    return sum / ((1.0f - 2.0f / (3.0f * cone_k)) * pi * radius2);
}

}  // namespace caustica
