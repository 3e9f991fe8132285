// A hashed grid over one pass's photons, made for the fixed-radius gathers of progressive photon
// mapping: built in O(n) each pass (a counting sort of the photons by the hash of their cell),
// queried by scanning the few cells a gather's sphere overlaps. Photons are stored as arrays of
// coordinates, powers and directions, sorted by bucket, so that a scan is a vectorised loop over
// contiguous floats. The k-d tree (photon_kdtree.h) stays for the k-nearest queries.
#pragma once

#include "core/photons/photon_map.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustica {

class PhotonGrid {
public:
    /// What a gather found: the power of the photons within the radius that arrive at the side the
    /// normal faces, of those within radius / sqrt 2 (the bias probe), and how many were summed.
    struct Gather {
        glm::vec3 sum{0.0f}, inner{0.0f};
        std::uint32_t count = 0;
    };

    PhotonGrid() = default;

    /// Sorts `photons` into cells of edge `cell` (> 0): a gather of radius up to cell / 2 scans at
    /// most 8 cells. The photons' order decides the order sums are made in: the same photons give
    /// the same bits whatever the thread count.
    void build(const std::vector<Photon>& photons, float cell);

    /// The photons within `radius` of `p` whose direction of travel is against `n` (they arrive
    /// at the side n faces), summed in a fixed order.
    Gather gather(const glm::vec3& p, const glm::vec3& n, float radius) const;

    std::size_t size() const { return photons_; }
    float cell() const { return cell_; }
    /// Bytes held (reused by the next build when it fits).
    std::size_t memory_bytes() const;

private:
    std::uint64_t bucket_of(std::int64_t i, std::int64_t j, std::int64_t k) const;

    float cell_ = 1.0f, inverse_cell_ = 1.0f;
    std::uint64_t mask_ = 0;             // buckets - 1 (a power of two)
    std::vector<std::uint32_t> start_;   // per bucket its first block; buckets + 1 entries
    std::vector<std::uint32_t> scratch_; // build: each photon's bucket
    std::vector<std::uint32_t> cursor_;  // build: per bucket its first photon in `order_` (buckets + 1)
    std::vector<std::uint32_t> order_;   // build: the photons' indices, bucket by bucket
    /// The photons in blocks of 8 (one run is whole blocks): per block 8 x, 8 y, 8 z, 8 of each
    /// power channel and of each direction component, 72 floats in a row, so a scan reads
    /// contiguous memory.
    std::vector<float> blocks_;
    std::size_t photons_ = 0;
};

}  // namespace caustica
