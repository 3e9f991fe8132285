#include "core/photons/photon_map.h"

#include "core/util/radiance_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustica {
namespace {
constexpr float pi = 3.14159265358979323846f;
constexpr float cone_k = 1.1f;
}  // namespace

PhotonMap::PhotonMap(const std::vector<Photon>& photons) {
    std::vector<glm::vec3> positions(photons.size());
    for (std::size_t i = 0; i < photons.size(); ++i) positions[i] = photons[i].position;
    tree_ = PhotonKdTree(std::move(positions));
    photons_.resize(photons.size());
    for (std::size_t i = 0; i < photons.size(); ++i) photons_[i] = photons[tree_.order()[i]];
}

glm::vec3 PhotonMap::estimate(const glm::vec3& p, const glm::vec3& n, int k, float max_distance,
                              PhotonFilter filter, Neighbour* scratch) const {
    Probe unused;
    return estimate(p, n, k, max_distance, filter, scratch, unused);
}

glm::vec3 PhotonMap::estimate(const glm::vec3& p, const glm::vec3& n, int k, float max_distance,
                              PhotonFilter filter, Neighbour* scratch, Probe& probe) const {
    probe = Probe{};
    const std::uint32_t found = tree_.nearest(p, static_cast<std::uint32_t>(k), max_distance, scratch);
    if (found == 0) return glm::vec3(0.0f);
    // Radius of the disc holding them: the k-th photon's distance, or the search radius.
    const float radius2 = found == static_cast<std::uint32_t>(k) ? scratch[0].distance2 : max_distance * max_distance;
    if (!(radius2 > 0.0f)) return glm::vec3(0.0f);
    glm::vec3 sum(0.0f), inner(0.0f);
    for (std::uint32_t i = 0; i < found; ++i) {
        const Photon& photon = photons_[scratch[i].index];
        if (glm::dot(photon.direction, n) < 0.0f) {
            sum += photon.power;
            if (scratch[i].distance2 < 0.5f * radius2) inner += photon.power;
        }
    }
    probe.inner = inner / (0.5f * pi * radius2);
    if (filter == PhotonFilter::none) return sum / (pi * radius2);
    const float radius = std::sqrt(radius2);
    sum = glm::vec3(0.0f);
    for (std::uint32_t i = 0; i < found; ++i) {
        const Photon& photon = photons_[scratch[i].index];
        if (glm::dot(photon.direction, n) >= 0.0f) continue;
        const float weight = 1.0f - std::sqrt(scratch[i].distance2) / (cone_k * radius);
        if (weight > 0.0f) sum += weight * photon.power;
    }
    return sum / ((1.0f - 2.0f / (3.0f * cone_k)) * pi * radius2);
}

ClassicEstimate PhotonMap::classic_estimate(const glm::vec3& p, int k, float prune_distance,
                                            Neighbour* scratch) const {
    ClassicEstimate e;
    if (k <= 0) return e;
    e.photons = tree_.nearest_always(p, static_cast<std::uint32_t>(k), prune_distance, scratch);
    if (e.photons == 0) return e;
    float radius2 = 0.0f;
    glm::vec3 sum(0.0f);
    for (std::uint32_t i = 0; i < e.photons; ++i) {
        radius2 = std::max(radius2, scratch[i].distance2);
        sum += photons_[scratch[i].index].power;
    }
    e.radius = std::sqrt(radius2);
    if (radius2 > 0.0f) e.value = saturate(sum / (pi * radius2));  // photons a hair apart: no infinity
    return e;
}

const Photon* PhotonMap::nearest_photon(const glm::vec3& p, float* distance) const {
    Neighbour nearest;
    if (tree_.nearest_always(p, 1, std::numeric_limits<float>::infinity(), &nearest) == 0) return nullptr;
    if (distance) *distance = std::sqrt(nearest.distance2);
    return &photons_[nearest.index];
}

glm::vec3 PhotonMap::disc_estimate(const glm::vec3& p, const glm::vec3& n, float radius, glm::vec3* inner) const {
    glm::vec3 sum(0.0f), inner_sum(0.0f);
    const float inner2 = 0.5f * radius * radius;
    tree_.for_each_within(p, radius, [&](std::uint32_t i, float distance2) {
        if (glm::dot(photons_[i].direction, n) >= 0.0f) return;
        sum += photons_[i].power;
        if (distance2 < inner2) inner_sum += photons_[i].power;
    });
    const float area = pi * radius * radius;
    if (inner) *inner = inner_sum / (0.5f * area);
    return sum / area;
}

}  // namespace caustica
