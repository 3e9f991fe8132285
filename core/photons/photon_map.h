// The caustic photon map: stored photons in a k-D tree, and the radiance estimate
// (docs/CAUSTICS.md).
#pragma once

#include "core/photons/photon_kdtree.h"

#include <glm/glm.hpp>

#include <vector>

namespace caustica {

/// A photon as stored at a diffuse surface: where, how much power, travelling which way.
struct Photon {
    glm::vec3 position;
    glm::vec3 power;
    glm::vec3 direction;  ///< unit direction of travel when it arrived
};

/// How the N nearest photons are weighted in the estimate.
enum class PhotonFilter {
    none,  ///< the original's plain disc average
    cone,  ///< Jensen's cone filter, k = 1.1: w = 1 - d / (k r), normalised by 1 - 2 / (3k)
};

/// What the classic estimate found (docs/CAUSTICS.md, "estimate").
struct ClassicEstimate {
    glm::vec3 value{0.0f};      ///< Sum(power) / (pi r^2), 0 without photons or when r = 0
    std::uint32_t photons = 0;  ///< photons returned: min(k, size())
    float radius = 0.0f;        ///< r: the largest distance among them
};

/// Photons in tree order with their k-D tree.
class PhotonMap {
public:
    PhotonMap() = default;
    /// Builds the k-D tree (O(n log n)) and stores a copy of the photons in its order.
    explicit PhotonMap(const std::vector<Photon>& photons);
    /// The photons, in tree order.
    const std::vector<Photon>& photons() const { return photons_; }

    /// Irradiance-like estimate at a surface point with unit normal `n` (facing the viewer): the
    /// power of the `k` nearest photons within `max_distance` arriving from the front side, over
    /// the area of the disc holding them: pi r^2 with r the distance of the k-th photon
    /// (docs/CAUSTICS.md, "The radiance estimate"). When fewer than k photons lie within
    /// max_distance, the disc searched (radius max_distance) is used instead, so isolated photons do
    /// not make bright spots.
    /// `scratch` must hold k entries.
    glm::vec3 estimate(const glm::vec3& p, const glm::vec3& n, int k, float max_distance, PhotonFilter filter,
                       Neighbour* scratch) const;
    /// The same with the progressive bias probe: `probe` gets the unfiltered estimate over the
    /// inner disc of half the area (radius r / sqrt 2).
    struct Probe {
        glm::vec3 inner{0.0f};
    };
    glm::vec3 estimate(const glm::vec3& p, const glm::vec3& n, int k, float max_distance, PhotonFilter filter,
                       Neighbour* scratch, Probe& probe) const;

    /// The classic radiance estimate ("estimate"): the power of the min(k, size()) photons that
    /// PhotonKdTree::nearest_always returns, over pi r^2 with r the largest distance among them.
    /// No filter, no side or normal test. `scratch` must hold k entries.
    ClassicEstimate classic_estimate(const glm::vec3& p, int k, float prune_distance, Neighbour* scratch) const;

    /// Progressive photon mapping's gather: the power of the photons within `radius` of `p`
    /// arriving from the front of the surface (normal `n` facing the viewer), over pi radius^2.
    /// `inner` gets the same estimate over the disc of radius r / sqrt 2 (from the same walk): the
    /// two differ by about half the radius bias r^2/8 Laplacian(E) (bias probe, docs/CAUSTICS.md).
    glm::vec3 disc_estimate(const glm::vec3& p, const glm::vec3& n, float radius, glm::vec3* inner = nullptr) const;

    /// The photon nearest to `p` however far (null for an empty map); its distance goes to
    /// `distance` when given. For the photon dot views ("debug views").
    const Photon* nearest_photon(const glm::vec3& p, float* distance = nullptr) const;

    /// The photon at tree position i.
    const Photon& photon(std::size_t i) const { return photons_[i]; }
    std::size_t size() const { return photons_.size(); }
    const PhotonKdTree& tree() const { return tree_; }
    std::size_t memory_bytes() const { return tree_.memory_bytes() + photons_.size() * sizeof(Photon); }

private:
    PhotonKdTree tree_;
    std::vector<Photon> photons_;
};

}  // namespace caustica
