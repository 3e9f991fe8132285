#include "core/geometry/csg_tree.h"

#include "core/geometry/ray.h"
#include "core/util/cancel_flag.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace caustica {
namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();

/// Upper limit on the surface crossings gathered from one mesh along one line.
constexpr int max_mesh_crossings = 1024;

bool box_is_empty(const glm::vec3& lo, const glm::vec3& hi) { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }

/// Where the line o + t d is inside the box, clipped to [t0, t1]; false when that is empty.
bool clip_line_to_box(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& o, const glm::vec3& d, float& t0,
                      float& t1) {
    if (box_is_empty(lo, hi)) return false;
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0.0f) {
            if (o[axis] < lo[axis] || o[axis] > hi[axis]) return false;
            continue;
        }
        float near = (lo[axis] - o[axis]) / d[axis], far = (hi[axis] - o[axis]) / d[axis];
        if (near > far) std::swap(near, far);
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
        if (!(t0 <= t1)) return false;
    }
    return true;
}

/// 1 / d per axis, with a huge finite value for a zero component so that slab tests never
/// compute 0 * infinity.
glm::vec3 safe_reciprocal(const glm::vec3& d) {
    glm::vec3 r;
    for (int axis = 0; axis < 3; ++axis)
        r[axis] = std::fabs(d[axis]) > 1e-30f ? 1.0f / d[axis] : std::numeric_limits<float>::max();
    return r;
}

/// The branch-free slab test of the per-node box culling: whether the line meets a (non-empty)
/// box within [t0, t1]. Conservative where a zero direction component makes it approximate.
bool box_meets_range(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& o, const glm::vec3& inv_d, float t0,
                     float t1) {
    const glm::vec3 a = (lo - o) * inv_d, b = (hi - o) * inv_d;
    const glm::vec3 near = glm::min(a, b), far = glm::max(a, b);
    return std::max(std::max(near.x, near.y), std::max(near.z, t0)) <=
           std::min(std::min(far.x, far.y), std::min(far.z, t1));
}

}  // namespace

void transformed_box(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& m, glm::vec3& out_lo,
                     glm::vec3& out_hi) {
    out_lo = glm::vec3(infinity);
    out_hi = glm::vec3(-infinity);
    if (box_is_empty(lo, hi)) return;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
        const glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
        out_lo = glm::min(out_lo, w);
        out_hi = glm::max(out_hi, w);
    }
    const glm::vec3 pad = 1e-5f * (out_hi - out_lo) + 1e-6f * glm::max(glm::abs(out_lo), glm::abs(out_hi));
    out_lo -= pad;
    out_hi += pad;
}

void mesh_leaf_segments(const CsgLeaf& leaf, int leaf_index, const glm::vec3& o, const glm::vec3& d, float box_in,
                        float box_out, CsgSegmentList& out) {
    out.clear();
    const MeshData& mesh = *leaf.mesh;
    const glm::vec3 oo = glm::vec3(leaf.world_to_object * glm::vec4(o, 1.0f));
    const glm::vec3 dd = glm::mat3(leaf.world_to_object) * d;
    const float speed = glm::length(dd);
    if (!(speed > 0.0f) || !leaf.mesh_scene) return;
    const float step = leaf.mesh_step / speed;  // in units of t
    // Start just outside the box, where the line is certainly outside the mesh.
    const float start = box_in - 2.0f * step;
    const glm::vec3 origin = oo + start * dd;
    const float span = box_out + 2.0f * step - start;
    if (!embree_traceable(origin, dd, 0.0f, span)) return;  // numerically out of reach: no crossings
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    int depth = 0, last_kind = 0;
    float last_t = -infinity, tnear = 0.0f;
    CsgSegment open;
    for (int i = 0; i < max_mesh_crossings && tnear <= span; ++i) {
        RTCRayHit rh;
        rh.ray.org_x = origin.x, rh.ray.org_y = origin.y, rh.ray.org_z = origin.z;
        rh.ray.dir_x = dd.x, rh.ray.dir_y = dd.y, rh.ray.dir_z = dd.z;
        rh.ray.tnear = tnear;
        rh.ray.tfar = span;
        rh.ray.mask = 0xffffffffu;
        rh.ray.flags = 0;
        rh.ray.time = 0.0f;
        rh.ray.id = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(leaf.mesh_scene, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        const float t = rh.ray.tfar;
        tnear = t + step;
        const glm::uvec3 tri = mesh.triangles[rh.hit.primID];
        const glm::vec3 v0 = mesh.positions[tri.x], v1 = mesh.positions[tri.y], v2 = mesh.positions[tri.z];
        const glm::vec3 normal = glm::cross(v1 - v0, v2 - v0);  // counter-clockwise = outward
        const float facing = glm::dot(normal, dd);
        if (facing == 0.0f) continue;  // edge-on: not a crossing
        const int kind = facing < 0.0f ? 1 : -1;  // entering : leaving
        // Through a shared edge or vertex the same crossing can be reported by two triangles.
        if (kind == last_kind && t - last_t <= 4.0f * step) continue;
        last_kind = kind;
        last_t = t;
        const CsgCrossing c{start + t, normal, leaf.material, leaf_index, static_cast<int>(rh.hit.primID), false};
        if (kind > 0) {
            if (depth++ == 0) open.enter = c;
        } else if (depth > 0 && --depth == 0) {
            open.leave = c;
            open.medium = leaf.material;
            out.push_back(open);
        }
    }
}

CsgTree::CsgTree(const FlatCsgObject& object, const SceneDesc& desc, int default_material,
                 const std::function<RTCScene(int)>& mesh_scene)
    : source_node_(object.node) {
    for (const PlacedPrimitive& p : object.leaves) {
        CsgLeaf leaf;
        const glm::mat4 to_world(p.object_to_world);
        leaf.world_to_object = glm::mat4(glm::inverse(p.object_to_world));
        leaf.object_to_world = glm::mat3(to_world);
        leaf.normal_to_world = glm::mat3(glm::transpose(glm::inverse(p.object_to_world)));
        leaf.material = p.material >= 0 ? p.material : default_material;
        if (leaf.material >= 0 && static_cast<std::size_t>(leaf.material) < desc.materials.size()) {
            const MaterialDesc& m = desc.materials[static_cast<std::size_t>(leaf.material)];
            leaf.transparent = m.refractive_index.has_value() || m.air;
        }
        glm::vec3 lo(infinity), hi(-infinity);
        if (p.is_mesh) {
            leaf.is_mesh = true;
            leaf.mesh = desc.meshes.at(static_cast<std::size_t>(p.mesh)).get();
            leaf.mesh_scene = mesh_scene(p.mesh);
            for (const glm::vec3& v : leaf.mesh->positions) {
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
            leaf.mesh_step = box_is_empty(lo, hi) ? 0.0f : 1e-6f * glm::length(hi - lo);
        } else {
            leaf.shape = p.shape;
            shape_bounds(p.shape, lo, hi);
        }
        transformed_box(lo, hi, to_world, leaf.lo, leaf.hi);
        leaves_.push_back(leaf);
    }
    root_ = build(object, object.root);
}

bool CsgTree::empty() const { return box_is_empty(lo(), hi()); }

int CsgTree::build(const FlatCsgObject& object, int flat_root) {
    using Kind = FlatCsgNode::Kind;
    // Post-order over the flat tree with an explicit stack: a script can nest operations as deeply
    // as it likes. A frame's operands are its two children, or for a union all the non-union
    // nodes of the union chain below it, in order.
    struct Frame {
        int flat;
        std::vector<int> operands;  // flat nodes still to build, in order
        std::size_t next = 0;
        std::vector<int> built;     // their tree nodes
    };
    std::vector<Frame> stack;
    auto open = [&](int flat_index) {
        Frame frame{flat_index, {}, 0, {}};
        const FlatCsgNode& flat = object.nodes.at(static_cast<std::size_t>(flat_index));
        if (flat.kind == Kind::unite) {
            // Union is associative, media included (the later operand wins either way), so a chain
            // such as u = union(u, x) in a script loop is rebuilt balanced for its boxes.
            std::vector<int> pending{flat_index};
            while (!pending.empty()) {
                const int i = pending.back();
                pending.pop_back();
                const FlatCsgNode& n = object.nodes.at(static_cast<std::size_t>(i));
                if (n.kind == Kind::unite) {
                    pending.push_back(n.right);
                    pending.push_back(n.left);
                } else {
                    frame.operands.push_back(i);
                }
            }
        } else if (flat.kind != Kind::leaf) {
            frame.operands = {flat.left, flat.right};
        }
        stack.push_back(std::move(frame));
    };
    int result = -1;
    open(flat_root);
    while (!stack.empty()) {
        Frame& top = stack.back();
        if (top.next < top.operands.size()) {
            open(top.operands[top.next++]);  // invalidates `top`
            continue;
        }
        const int built = finish_node(object, top.flat, top.built);
        stack.pop_back();
        if (stack.empty()) result = built;
        else stack.back().built.push_back(built);
    }
    return result;
}

int CsgTree::finish_node(const FlatCsgObject& object, int flat_index, const std::vector<int>& operands) {
    using Kind = FlatCsgNode::Kind;
    const FlatCsgNode& flat = object.nodes.at(static_cast<std::size_t>(flat_index));
    Node node;
    node.kind = flat.kind;
    if (flat.kind == Kind::leaf) {
        node.leaf = flat.leaf;
        node.lo = leaves_[static_cast<std::size_t>(flat.leaf)].lo;
        node.hi = leaves_[static_cast<std::size_t>(flat.leaf)].hi;
    } else if (flat.kind == Kind::unite) {
        std::vector<int> level = operands;
        while (level.size() > 1) {  // pair neighbours level by level, keeping their order
            std::vector<int> next;
            for (std::size_t i = 0; i + 1 < level.size(); i += 2) {
                Node u;
                u.kind = Kind::unite;
                u.left = level[i];
                u.right = level[i + 1];
                u.lo = glm::min(nodes_[static_cast<std::size_t>(u.left)].lo, nodes_[static_cast<std::size_t>(u.right)].lo);
                u.hi = glm::max(nodes_[static_cast<std::size_t>(u.left)].hi, nodes_[static_cast<std::size_t>(u.right)].hi);
                u.empty_box = box_is_empty(u.lo, u.hi);
                nodes_.push_back(u);
                next.push_back(static_cast<int>(nodes_.size()) - 1);
            }
            if (level.size() % 2 == 1) next.push_back(level.back());
            level = std::move(next);
        }
        return level.front();
    } else {
        node.left = operands[0];
        node.right = operands[1];
        const Node& l = nodes_[static_cast<std::size_t>(node.left)];
        const Node& r = nodes_[static_cast<std::size_t>(node.right)];
        node.lo = l.lo;
        node.hi = l.hi;
        if (flat.kind == Kind::intersect) {
            node.lo = glm::max(l.lo, r.lo);
            node.hi = glm::min(l.hi, r.hi);
        }
    }
    node.empty_box = box_is_empty(node.lo, node.hi);
    nodes_.push_back(node);
    return static_cast<int>(nodes_.size()) - 1;
}

void CsgTree::evaluate(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar, CsgSegmentList& out,
                       const std::atomic<bool>* cancel) const {
    const float pad = 2.0f * epsilon_ / std::max(glm::length(d), 1e-30f);
    const LineQuery q{o, d, safe_reciprocal(d), tnear - pad, tfar + pad, cancel};
    out.clear();
    if (!worth_visiting(root_, q)) return;
    evaluate_node(root_, q, out, 0);
}

CsgTree::Plan CsgTree::plan(const Node& node, const LineQuery& q) const {
    // The children's boxes decide what is evaluated at all: an operand the line misses is empty,
    // so a union is the other operand's list and a difference the first operand's.
    const bool left_seen = worth_visiting(node.left, q), right_seen = worth_visiting(node.right, q);
    const bool empty = node.kind == FlatCsgNode::Kind::unite
                           ? !left_seen && !right_seen
                           : !left_seen || (node.kind == FlatCsgNode::Kind::intersect && !right_seen);
    if (empty) return Plan::nothing;
    if (!right_seen) return Plan::left_only;
    if (!left_seen) return Plan::right_only;
    return Plan::both;
}

void CsgTree::combine(const Node& node, const CsgSegmentList& left, const CsgSegmentList& right,
                      CsgSegmentList& out) const {
    switch (node.kind) {
        case FlatCsgNode::Kind::unite: csg_union(left, right, epsilon_, out); return;
        case FlatCsgNode::Kind::intersect: csg_intersection(left, right, epsilon_, out); return;
        case FlatCsgNode::Kind::subtract: csg_difference(left, right, epsilon_, out); return;
        case FlatCsgNode::Kind::leaf: return;
    }
}

void CsgTree::evaluate_node(int index, const LineQuery& q, CsgSegmentList& out, int depth) const {
    // Recursion is the fastest walk for the shallow trees of real scenes (unions are balanced at
    // build); a subtree deeper than this goes to the explicit stack, so no script can exhaust
    // the C stack (a frame holds two lists: about 1.2 KiB).
    constexpr int max_recursion = 48;
    if (depth >= max_recursion) {
        evaluate_deep(index, q, out);
        return;
    }
    const Node& node = nodes_[static_cast<std::size_t>(index)];
    if (node.kind == FlatCsgNode::Kind::leaf) {
        leaf_segments(node.leaf, q, out);
        return;
    }
    switch (plan(node, q)) {
        case Plan::nothing: out.clear(); return;
        case Plan::left_only: evaluate_node(node.left, q, out, depth + 1); return;
        case Plan::right_only: evaluate_node(node.right, q, out, depth + 1); return;
        case Plan::both: break;
    }
    CsgSegmentList left;
    evaluate_node(node.left, q, left, depth + 1);
    if (left.empty() && node.kind != FlatCsgNode::Kind::unite) {
        out.clear();
        return;
    }
    CsgSegmentList right;
    evaluate_node(node.right, q, right, depth + 1);
    combine(node, left, right, out);
}

namespace {

/// Per-thread working storage of CsgTree::evaluate_deep: the pending nodes, a pool of interval
/// lists and the stack of results (pool slots). Kept between calls, so that evaluation allocates
/// nothing once warmed up, and results move by slot number instead of being copied.
struct CsgWorkspace {
    struct Step {
        int node;
        int stage;  // 0 = not started, 1 = left operand evaluated, 2 = both evaluated
    };
    std::vector<Step> steps;
    std::vector<CsgSegmentList> pool;
    std::vector<int> free_slots;
    std::vector<int> results;

    /// An empty list's slot (the pool may grow: take references only after this).
    int take() {
        if (free_slots.empty()) {
            pool.emplace_back();
            return static_cast<int>(pool.size()) - 1;
        }
        const int slot = free_slots.back();
        free_slots.pop_back();
        pool[static_cast<std::size_t>(slot)].clear();
        return slot;
    }
    void give_back(int slot) { free_slots.push_back(slot); }
    CsgSegmentList& list(int slot) { return pool[static_cast<std::size_t>(slot)]; }
};

thread_local CsgWorkspace csg_workspace;

}  // namespace

void CsgTree::evaluate_deep(int index, const LineQuery& q, CsgSegmentList& out) const {
    using Kind = FlatCsgNode::Kind;
    // evaluate_node's walk with an explicit stack: each node leaves its interval list on the
    // result stack; an operation replaces its operands' two lists by their combination.
    CsgWorkspace& w = csg_workspace;
    const std::size_t base_steps = w.steps.size(), base_results = w.results.size();
    w.steps.push_back({index, 0});
    while (w.steps.size() > base_steps) {
        const CsgWorkspace::Step step = w.steps.back();
        const Node& node = nodes_[static_cast<std::size_t>(step.node)];
        if (node.kind == Kind::leaf) {
            w.steps.pop_back();
            const int slot = w.take();
            leaf_segments(node.leaf, q, w.list(slot));
            w.results.push_back(slot);
            continue;
        }
        if (step.stage == 0) {
            switch (plan(node, q)) {
                case Plan::nothing:
                    w.steps.pop_back();
                    w.results.push_back(w.take());
                    break;
                case Plan::left_only: w.steps.back() = {node.left, 0}; break;  // this node is its operand
                case Plan::right_only: w.steps.back() = {node.right, 0}; break;
                case Plan::both:
                    w.steps.back().stage = 1;
                    w.steps.push_back({node.left, 0});
                    break;
            }
            continue;
        }
        if (step.stage == 1) {
            if (w.list(w.results.back()).empty() && node.kind != Kind::unite) {
                w.steps.pop_back();  // nothing to intersect or subtract from: the empty list stands
            } else {
                w.steps.back().stage = 2;
                w.steps.push_back({node.right, 0});
            }
            continue;
        }
        w.steps.pop_back();
        const int right = w.results.back();
        w.results.pop_back();
        const int left = w.results.back();
        const int result = w.take();  // the pool may grow: references after this
        combine(node, w.list(left), w.list(right), w.list(result));
        w.give_back(left);
        w.give_back(right);
        w.results.back() = result;
    }
    const int root = w.results.back();
    w.results.resize(base_results);
    out = w.list(root);
    w.give_back(root);
}

bool CsgTree::first_boundary(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar, CsgSegmentList& list,
                             CsgBoundary& out, const std::atomic<bool>* cancel) const {
    evaluate(o, d, tnear, tfar, list, cancel);
    if (!csg_first_boundary(list, tnear, tfar, out)) return false;
    const CsgCrossing& surface = *out.surface;
    if (surface.carved && leaves_[static_cast<std::size_t>(surface.leaf)].transparent)
        out.medium_inside = surface.material;
    return true;
}

bool CsgTree::worth_visiting(int index, const LineQuery& q) const {
    if (!use_boxes_) return true;
    const Node& node = nodes_[static_cast<std::size_t>(index)];
    return !node.empty_box && box_meets_range(node.lo, node.hi, q.o, q.inv_d, q.range_lo, q.range_hi);
}

void CsgTree::leaf_segments(int leaf_index, const LineQuery& q, CsgSegmentList& out) const {
    out.clear();
    if (is_cancelled(q.cancel)) return;
    const CsgLeaf& leaf = leaves_[static_cast<std::size_t>(leaf_index)];
    if (leaf.is_mesh) {
        // The mesh is traced from where the line enters its box, so that its crossings can be
        // paired from outside.
        float t0 = -infinity, t1 = infinity;
        if (!clip_line_to_box(leaf.lo, leaf.hi, q.o, q.d, t0, t1)) return;
        mesh_leaf_segments(leaf, leaf_index, q.o, q.d, t0, t1, out);
        return;
    }
    const glm::vec3 oo = glm::vec3(leaf.world_to_object * glm::vec4(q.o, 1.0f));
    const glm::vec3 dd = glm::mat3(leaf.world_to_object) * q.d;
    ShapeInterval interval;
    if (!intersect_shape_interval(leaf.shape, oo, dd, interval)) return;
    // Written in place, field by field (see copy_crossing).
    CsgSegment& s = out.append();
    auto crossing = [&](CsgCrossing& c, const SurfaceCrossing& from) {
        c.t = from.t;
        c.normal = from.normal;
        c.material = leaf.material;
        c.leaf = leaf_index;
        c.face = from.face;
        c.mirrored = false;
        c.carved = false;
    };
    crossing(s.enter, interval.entry);
    crossing(s.leave, interval.exit);
    s.medium = leaf.material;
}

}  // namespace caustica
