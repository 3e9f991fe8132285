#include "core/photons/photon_kdtree.h"

#include <algorithm>
#include <limits>

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

    /// Builds the subtree over entries [begin, end) whose points lie in the box [lo, hi].
    std::uint32_t build(std::uint32_t begin, std::uint32_t end, glm::vec3 lo, glm::vec3 hi) {
        const auto index = static_cast<std::uint32_t>(tree.nodes_.size());
        tree.nodes_.push_back({});
        if (end - begin <= leaf_size) {
            tree.nodes_[index] = {0.0f, leaf_tag, begin, end};
            return index;
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
        build(begin, mid, lo, left_hi);
        const std::uint32_t right = build(mid, end, right_lo, hi);
        tree.nodes_[index] = {split, static_cast<std::uint32_t>(axis), right, 0};
        return index;
    }
};

PhotonKdTree::PhotonKdTree(std::vector<glm::vec3> points) {
    const auto n = static_cast<std::uint32_t>(points.size());
    if (n == 0) return;
    Builder builder{*this, std::vector<BuildEntry>(n)};
    lo_ = hi_ = points[0];
    for (std::uint32_t i = 0; i < n; ++i) {
        builder.entries[i] = {points[i], i};
        lo_ = glm::min(lo_, points[i]);
        hi_ = glm::max(hi_, points[i]);
    }
    points.clear();
    points.shrink_to_fit();
    nodes_.reserve(2 * (n / leaf_size + 1));
    builder.build(0, n, lo_, hi_);
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
    float radius2 = max_distance * max_distance;
    // Skip the whole search when the photons' bounds are out of reach.
    const glm::vec3 outside = glm::max(glm::max(lo_ - query, query - hi_), glm::vec3(0.0f));
    if (glm::dot(outside, outside) >= radius2) return 0;

    struct Pending {
        std::uint32_t node;
        float plane_distance2;
    };
    Pending stack[64];
    int depth = 0;
    std::uint32_t count = 0;
    std::uint32_t node = 0;
    for (;;) {
        const Node& n = nodes_[node];
        if (n.axis_or_leaf != leaf_tag) {
            const float d = query[n.axis_or_leaf] - n.split;
            const std::uint32_t near = d < 0.0f ? node + 1 : n.a;
            const std::uint32_t far = d < 0.0f ? n.a : node + 1;
            if (d * d < radius2) stack[depth++] = {far, d * d};
            node = near;
            continue;
        }
        for (std::uint32_t i = n.a; i < n.b; ++i) {
            const glm::vec3 v = points_[i] - query;
            const float d2 = glm::dot(v, v);
            if (d2 >= radius2) continue;
            if (count < k) {
                result[count++] = {d2, i};
                std::push_heap(result, result + count);
                if (count == k) radius2 = result[0].distance2;
            } else {
                std::pop_heap(result, result + k);
                result[k - 1] = {d2, i};
                std::push_heap(result, result + k);
                radius2 = result[0].distance2;
            }
        }
        // Resume at the nearest pending subtree still within reach.
        while (depth > 0 && stack[depth - 1].plane_distance2 >= radius2) --depth;
        if (depth == 0) break;
        node = stack[--depth].node;
    }
    return count;
}

std::uint32_t PhotonKdTree::nearest_always(const glm::vec3& query, std::uint32_t k, float prune_distance,
                                           Neighbour* result) const {
    if (nodes_.empty() || k == 0) return 0;
    const float prune2 = prune_distance * prune_distance;
    struct Pending {
        std::uint32_t node;
        float plane_distance2;
    };
    Pending stack[64];  // the tree is balanced: its depth is about log2(n / leaf_size) < 32
    int depth = 0;
    std::uint32_t count = 0;
    // Subtrees farther than this are skipped: nothing until k are held, then the smaller of the
    // prune distance and the farthest held.
    float bound2 = std::numeric_limits<float>::infinity();
    std::uint32_t node = 0;
    for (;;) {
        const Node& n = nodes_[node];
        if (n.axis_or_leaf != leaf_tag) {
            const float d = query[n.axis_or_leaf] - n.split;
            const std::uint32_t near = d < 0.0f ? node + 1 : n.a;
            const std::uint32_t far = d < 0.0f ? n.a : node + 1;
            if (d * d < bound2) stack[depth++] = {far, d * d};
            node = near;
            continue;
        }
        for (std::uint32_t i = n.a; i < n.b; ++i) {
            const glm::vec3 v = points_[i] - query;
            const float d2 = glm::dot(v, v);
            if (count < k) {
                result[count++] = {d2, i};
                std::push_heap(result, result + count);
                if (count == k) bound2 = std::min(prune2, result[0].distance2);
            } else if (d2 < result[0].distance2) {
                std::pop_heap(result, result + k);
                result[k - 1] = {d2, i};
                std::push_heap(result, result + k);
                bound2 = std::min(prune2, result[0].distance2);
            }
        }
        while (depth > 0 && stack[depth - 1].plane_distance2 >= bound2) --depth;
        if (depth == 0) break;
        node = stack[--depth].node;
    }
    return count;
}

std::size_t PhotonKdTree::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + points_.size() * sizeof(glm::vec3) + order_.size() * sizeof(std::uint32_t);
}

}  // namespace caustica
