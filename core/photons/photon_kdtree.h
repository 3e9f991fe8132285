// Our photon k-D tree (docs/CAUSTICS.md, "The k-D tree"): built in O(n log n) by median selection
// (nth_element, not a sort), stored flat (one node array, photons reordered so every leaf is a
// contiguous run), with N-nearest queries bounded by a maximum distance through a fixed-size
// max-heap.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace caustica {

/// One neighbour found by a query: the photon's index (in tree order) and squared distance.
struct Neighbour {
    float distance2;
    std::uint32_t index;
    bool operator<(const Neighbour& o) const { return distance2 < o.distance2; }
};

/// A static 3-d tree over points; the caller keeps per-point data in `order()` order.
class PhotonKdTree {
public:
    /// Photons per leaf; small runs are scanned linearly, which beats descending further.
    static constexpr std::uint32_t leaf_size = 12;

    PhotonKdTree() = default;

    /// Builds the tree over `points`. Afterwards point i of the tree is `points[order()[i]]`.
    explicit PhotonKdTree(std::vector<glm::vec3> points);

    /// Finds up to `k` nearest points within `max_distance` of `query`, nearest first... in heap
    /// order (the farthest is `result[0]`); returns how many were found. `result` must hold `k`.
    std::uint32_t nearest(const glm::vec3& query, std::uint32_t k, float max_distance, Neighbour* result) const;

    /// The classic search (docs/CAUSTICS.md, "search"): always finds min(k, size()) points, in heap
    /// order (the farthest is `result[0]`). Nearer side first; while fewer than k are held every
    /// point visited is taken however far; once k are held a point replaces the farthest held when
    /// closer, and subtrees are pruned against min(prune_distance, farthest held). So the result is
    /// the exact k nearest whenever they all lie within prune_distance. `result` must hold `k`.
    std::uint32_t nearest_always(const glm::vec3& query, std::uint32_t k, float prune_distance,
                                 Neighbour* result) const;

    /// Calls visit(index, distance2) for every point closer than `radius` to `query` (tree order,
    /// any order of visits): the fixed-radius gather of progressive photon mapping.
    template <typename Visit>
    void for_each_within(const glm::vec3& query, float radius, Visit&& visit) const {
        if (nodes_.empty() || !(radius > 0.0f)) return;
        const float radius2 = radius * radius;
        const glm::vec3 outside = glm::max(glm::max(lo_ - query, query - hi_), glm::vec3(0.0f));
        if (glm::dot(outside, outside) >= radius2) return;
        walk(query, radius2, [&](std::uint32_t i, float distance2) {
            if (distance2 < radius2) visit(i, distance2);
            return radius2;  // a fixed bound: every subtree whose plane lies within the radius
        });
    }

    /// The points in tree order.
    const std::vector<glm::vec3>& points() const { return points_; }
    /// For each tree position, the index the point had in the input.
    const std::vector<std::uint32_t>& order() const { return order_; }
    std::size_t size() const { return points_.size(); }
    /// Bounds of all points (empty tree: lo > hi).
    glm::vec3 bounds_lo() const { return lo_; }
    glm::vec3 bounds_hi() const { return hi_; }
    /// Bytes held by the tree (nodes, points, order).
    std::size_t memory_bytes() const;

private:
    /// Inner node: split plane and right child; leaf: a run of points. 16 bytes.
    struct Node {
        float split;
        std::uint32_t axis_or_leaf;  ///< 0..2 = split axis, 3 = leaf
        std::uint32_t a, b;          ///< inner: right child (left is the next node); leaf: [a, b)
    };
    static constexpr std::uint32_t leaf_tag = 3;

    struct Builder;

    /// Near-side-first walk of the tree: calls visit(index, distance2) for every point of every
    /// leaf reached; visit returns the squared bound a pending subtree's splitting plane must be
    /// within to be visited (it may shrink as points are found). `bound2` is the first bound.
    template <typename Visit>
    void walk(const glm::vec3& query, float bound2, Visit&& visit) const {
        struct Pending {
            std::uint32_t node;
            float plane_distance2;
        };
        Pending stack[64];  // the tree is balanced: its depth is about log2(n / leaf_size) < 32
        int depth = 0;
        std::uint32_t node = 0;
        for (;;) {
            const Node& n = nodes_[node];
            if (n.axis_or_leaf != leaf_tag) {
                const float d = query[n.axis_or_leaf] - n.split;
                if (d * d < bound2) stack[depth++] = {d < 0.0f ? n.a : node + 1, d * d};
                node = d < 0.0f ? node + 1 : n.a;
                continue;
            }
            for (std::uint32_t i = n.a; i < n.b; ++i) {
                const glm::vec3 v = points_[i] - query;
                bound2 = visit(i, glm::dot(v, v));
            }
            // Resume at the nearest pending subtree still within reach.
            while (depth > 0 && stack[depth - 1].plane_distance2 >= bound2) --depth;
            if (depth == 0) break;
            node = stack[--depth].node;
        }
    }

    std::vector<Node> nodes_;
    std::vector<glm::vec3> points_;
    std::vector<std::uint32_t> order_;
    glm::vec3 lo_{1.0f}, hi_{-1.0f};
};

}  // namespace caustica
