#include "core/photons/photon_kdtree.h"
#include "core/util/parallel.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include <tbb/parallel_invoke.h>

namespace caustica {

namespace {

/// A point with its input index, moved as one 16-byte unit while the tree is built.
struct BuildEntry {
    glm::vec3 p;
    std::uint32_t index;
};

}  // namespace

struct PhotonKdTree::Builder {
    PhotonKdTree& tree;
    std::vector<BuildEntry> entries;
    std::unordered_map<std::uint32_t, std::uint32_t> node_counts;  // filled before the parallel build

    /// Nodes of a subtree of `n` points: fixed by n, so that every subtree knows where its nodes go
    /// (depth first, left subtree right after its parent) before its siblings are built.
    std::uint32_t nodes_for(std::uint32_t n) {
        if (n <= leaf_size) return 1;
        if (auto it = node_counts.find(n); it != node_counts.end()) return it->second;
        const std::uint32_t count = 1 + nodes_for(n / 2) + nodes_for(n - n / 2);
        node_counts.emplace(n, count);
        return count;
    }
    std::uint32_t nodes_for_built(std::uint32_t n) const {
        return n <= leaf_size ? 1 : node_counts.at(n);
    }

    /// Builds the subtree over entries [begin, end), whose points lie in the box [lo, hi], into
    /// the nodes from `index` on. Large subtrees build their halves in parallel: the halves are
    /// disjoint ranges of entries and of nodes, so the tree is the one a serial build makes.
    void build(std::uint32_t index, std::uint32_t begin, std::uint32_t end, glm::vec3 lo, glm::vec3 hi) {
        if (end - begin <= leaf_size) {
            tree.nodes_[index] = {0.0f, leaf_tag, begin, end};
            return;
        }
        // Split the box's longest side at the median point (selection: O(n) per level). The box
        // is the parent's cut at the split, so no pass over the points is needed to find it.
        const glm::vec3 extent = hi - lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(entries.begin() + begin, entries.begin() + mid, entries.begin() + end,
                         [axis](const BuildEntry& a, const BuildEntry& b) { return a.p[axis] < b.p[axis]; });
        const float split = entries[mid].p[axis];
        glm::vec3 left_hi = hi, right_lo = lo;
        left_hi[axis] = split;
        right_lo[axis] = split;
        const std::uint32_t right = index + 1 + nodes_for_built(mid - begin);
        tree.nodes_[index] = {split, static_cast<std::uint32_t>(axis), right, 0};
        if (end - begin >= parallel_points)
            caustica::parallel_invoke([&] { build(index + 1, begin, mid, lo, left_hi); },
                                 [&] { build(right, mid, end, right_lo, hi); });
        else {
            build(index + 1, begin, mid, lo, left_hi);
            build(right, mid, end, right_lo, hi);
        }
    }

    static constexpr std::uint32_t parallel_points = 1u << 15;
};

PhotonKdTree::PhotonKdTree(std::vector<glm::vec3> points) {
    const auto n = static_cast<std::uint32_t>(points.size());
    if (n == 0) return;
    Builder builder{*this, std::vector<BuildEntry>(n), {}};
    lo_ = hi_ = points[0];
    for (std::uint32_t i = 0; i < n; ++i) {
        builder.entries[i] = {points[i], i};
        lo_ = glm::min(lo_, points[i]);
        hi_ = glm::max(hi_, points[i]);
    }
    points.clear();
    points.shrink_to_fit();
    nodes_.resize(builder.nodes_for(n));
    builder.build(0, 0, n, lo_, hi_);
    points_.resize(n);
    order_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        points_[i] = builder.entries[i].p;
        order_[i] = builder.entries[i].index;
    }
}

std::uint32_t PhotonKdTree::nearest(const glm::vec3& query, std::uint32_t k, float max_distance,
                                    Neighbour* result) const {
    if (nodes_.empty() || k == 0) return 0;
    const float max2 = max_distance * max_distance;
    // Skip the whole search when the photons' bounds are out of reach.
    const glm::vec3 outside = glm::max(glm::max(lo_ - query, query - hi_), glm::vec3(0.0f));
    if (glm::dot(outside, outside) >= max2) return 0;
    std::uint32_t count = 0;
    walk(query, max2, [&](std::uint32_t i, float d2) {
        if (count < k) {
            if (d2 >= max2) return max2;
            result[count++] = {d2, i};
            std::push_heap(result, result + count);
            return count == k ? result[0].distance2 : max2;
        }
        if (d2 < result[0].distance2) {
            std::pop_heap(result, result + k);
            result[k - 1] = {d2, i};
            std::push_heap(result, result + k);
        }
        return result[0].distance2;
    });
    return count;
}

std::uint32_t PhotonKdTree::nearest_always(const glm::vec3& query, std::uint32_t k, float prune_distance,
                                           Neighbour* result) const {
    if (nodes_.empty() || k == 0) return 0;
    const float prune2 = prune_distance * prune_distance;
    std::uint32_t count = 0;
    // Subtrees farther than the bound are skipped: none until k are held, then the smaller of the
    // prune distance and the farthest held.
    walk(query, std::numeric_limits<float>::infinity(), [&](std::uint32_t i, float d2) {
        if (count < k) {
            result[count++] = {d2, i};
            std::push_heap(result, result + count);
            return count == k ? std::min(prune2, result[0].distance2) : std::numeric_limits<float>::infinity();
        }
        if (d2 < result[0].distance2) {
            std::pop_heap(result, result + k);
            result[k - 1] = {d2, i};
            std::push_heap(result, result + k);
        }
        return std::min(prune2, result[0].distance2);
    });
    return count;
}

std::size_t PhotonKdTree::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + points_.size() * sizeof(glm::vec3) + order_.size() * sizeof(std::uint32_t);
}

}  // namespace caustica
