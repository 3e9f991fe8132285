#include "core/scene/scene_flatten.h"

#include "core/scene/source_location.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <vector>

namespace caustica {
namespace {

glm::dmat4 op_matrix(const TransformOp& op) {
    switch (op.kind) {
        case TransformOp::Kind::translate: return glm::translate(glm::dmat4(1.0), op.amount);
        case TransformOp::Kind::scale: return glm::scale(glm::dmat4(1.0), op.amount);
        case TransformOp::Kind::rotate: {
            glm::dvec3 axis(0.0);
            axis[op.axis] = 1.0;
            return glm::rotate(glm::dmat4(1.0), glm::radians(op.degrees), axis);
        }
    }
    return glm::dmat4(1.0);
}

bool usable_transform(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    const double det = glm::determinant(glm::dmat3(m));
    // Relative to the scale of the matrix: a determinant this small means a collapsed axis.
    const double scale = glm::length(m[0]) * glm::length(m[1]) * glm::length(m[2]);
    return std::isfinite(det) && scale > 0.0 && std::fabs(det) > 1e-12 * scale;
}

/// Upper limit on the nodes one render expands to: reuse (instancing) multiplies a subtree by the
/// number of paths to it, so sixty script lines can describe 2^60 nodes. Five million expanded
/// nodes is far beyond the scenes the renderer is for (the course scenes expand to thousands) and
/// keeps the flattened scene (under 200 bytes per primitive) and its BVH within a few GB.
constexpr std::size_t max_expanded_nodes = 5'000'000;

bool is_csg(NodeKind kind) {
    return kind == NodeKind::csg_union || kind == NodeKind::csg_intersection || kind == NodeKind::csg_difference;
}

/// Walks the DAG with an explicit stack (a scene may nest nodes as deeply as it likes: no
/// recursion on the C stack). Each node is visited once per path from the root, in the order a
/// recursive pre-order walk would visit it, so the output is the same.
class Walker {
public:
    Walker(const SceneDesc& scene, bool course) : scene_(scene), course_(course), on_path_(scene.nodes.size(), 0) {}

    FlatScene run(int root) {
        start(root, glm::dmat4(1.0), -1, false);
        while (!frames_.empty()) step();
        return std::move(out_);
    }

private:
    /// One node on the path from the root, with what its subtree has produced so far.
    struct Frame {
        int index = -1;
        glm::dmat4 world{1.0};
        int material = -1;
        bool csg = false;          ///< inside a CSG object: the subtree becomes tree nodes
        bool object_root = false;  ///< the node that started the current CSG object
        /// 0 = left operand next, 1 = right operand next, 2 = right operand being expanded (CSG
        /// operations only), 3 = children
        int stage = 0;
        std::size_t next_child = 0;
        int left = -1;             ///< the left operand's tree node (CSG operations)
        std::vector<int> parts;    ///< tree nodes of the subtree, united at the end (CSG)
    };

    /// Enters a node: checks for cycles, the size of the expansion and the world transform,
    /// resolves the material and pushes its frame.
    void start(int index, const glm::dmat4& parent, int inherited_material, bool csg) {
        if (index < 0 || index >= static_cast<int>(scene_.nodes.size())) throw InputError("a node refers to a missing node");
        const NodeDesc& node = scene_.nodes[static_cast<std::size_t>(index)];
        if (!csg && is_csg(node.kind)) {  // the whole subtree becomes one CSG object
            object_ = FlatCsgObject{};
            object_.node = index;
            start(index, parent, inherited_material, true);
            frames_.back().object_root = true;
            return;
        }
        if (on_path_[static_cast<std::size_t>(index)])
            throw InputError(node.where, "node '" + node.name + "' contains itself");
        if (++expanded_ > max_expanded_nodes)
            throw InputError(node.where, "node '" + node.name + "': the scene expands to more than " +
                                             std::to_string(max_expanded_nodes) +
                                             " nodes (each reuse of a node copies its subtree)");
        Frame frame;
        frame.index = index;
        frame.csg = csg;
        frame.world = parent * compose_transforms(node.transforms, course_);
        if (!usable_transform(frame.world))
            throw InputError(node.where, "node '" + node.name + "': its world transform is singular or not finite");
        frame.material = node.material >= 0 ? node.material : inherited_material;
        if (csg && is_csg(node.kind)) {
            if (node.csg_left < 0 || node.csg_right < 0)
                throw InputError(node.where, "CSG node '" + node.name + "' needs two operands");
        } else {
            frame.stage = 3;
            PlacedPrimitive prim;
            if (own_primitive(index, node, frame.world, frame.material, prim)) {
                if (csg) {
                    object_.leaves.push_back(prim);
                    object_.nodes.push_back(
                        {FlatCsgNode::Kind::leaf, -1, -1, static_cast<int>(object_.leaves.size()) - 1});
                    frame.parts.push_back(static_cast<int>(object_.nodes.size()) - 1);
                } else {
                    out_.primitives.push_back(prim);
                }
            }
        }
        on_path_[static_cast<std::size_t>(index)] = 1;
        frames_.push_back(std::move(frame));
    }

    /// Advances the frame on top: starts its next operand or child, or finishes it.
    void step() {
        Frame& frame = frames_.back();
        const NodeDesc& node = scene_.nodes[static_cast<std::size_t>(frame.index)];
        const glm::dmat4 world = frame.world;
        const int material = frame.material;
        switch (frame.stage) {
            case 0: frame.stage = 1; start(node.csg_left, world, material, true); return;
            case 1: frame.stage = 2; start(node.csg_right, world, material, true); return;
            default: break;
        }
        if (frame.next_child < node.children.size()) {
            const int child = node.children[frame.next_child++];
            start(child, world, material, frame.csg);  // invalidates `frame`
            return;
        }
        finish();
    }

    /// Pops the frame on top; a CSG frame hands its tree node to its parent (or to its object).
    void finish() {
        Frame frame = std::move(frames_.back());
        frames_.pop_back();
        on_path_[static_cast<std::size_t>(frame.index)] = 0;
        if (!frame.csg) return;
        std::erase(frame.parts, -1);
        const int result = balanced_union(frame.parts, 0, frame.parts.size());
        if (frame.object_root) {
            object_.root = result;
            if (result >= 0) out_.csg_objects.push_back(std::move(object_));
            object_ = FlatCsgObject{};
            return;
        }
        Frame& parent = frames_.back();
        if (parent.stage == 1) {
            parent.left = result;
        } else if (parent.stage == 2) {
            const NodeKind kind = scene_.nodes[static_cast<std::size_t>(parent.index)].kind;
            const FlatCsgNode::Kind op = kind == NodeKind::csg_union          ? FlatCsgNode::Kind::unite
                                         : kind == NodeKind::csg_intersection ? FlatCsgNode::Kind::intersect
                                                                              : FlatCsgNode::Kind::subtract;
            parent.parts.push_back(combine(op, parent.left, result));
            parent.stage = 3;
        } else {
            parent.parts.push_back(result);
        }
    }

    /// The node's own primitive, if it is one (not a group or CSG node); warns when it has no material.
    bool own_primitive(int index, const NodeDesc& node, const glm::dmat4& world, int material, PlacedPrimitive& prim) {
        prim.object_to_world = world;
        prim.material = material;
        prim.node = index;
        switch (node.kind) {
            case NodeKind::group:
            case NodeKind::csg_union:
            case NodeKind::csg_intersection:
            case NodeKind::csg_difference: return false;
            case NodeKind::sphere: prim.shape = {ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)}; break;
            case NodeKind::nh_sphere:
                prim.shape = {ShapeKind::sphere, glm::vec3(node.position), glm::vec3(static_cast<float>(node.size))};
                break;
            case NodeKind::cube:
                prim.shape = course_ ? Shape{ShapeKind::box, glm::vec3(0.0f), glm::vec3(1.0f)}
                                     : Shape{ShapeKind::box, glm::vec3(-1.0f), glm::vec3(1.0f)};
                break;
            case NodeKind::nh_box:
                prim.shape = {ShapeKind::box, glm::vec3(node.position), glm::vec3(node.position + node.size)};
                break;
            case NodeKind::cylinder: prim.shape = {ShapeKind::cylinder, glm::vec3(0.0f), glm::vec3(1.0f)}; break;
            case NodeKind::cone: prim.shape = {ShapeKind::cone, glm::vec3(0.0f), glm::vec3(1.0f)}; break;
            case NodeKind::mesh:
                prim.is_mesh = true;
                prim.mesh = node.mesh;
                break;
        }
        if (material < 0)
            out_.warnings.push_back(node.where.str() + ": node '" + node.name + "' has no material; it is drawn in grey");
        return true;
    }

    /// Adds a CSG tree node; returns its index. Empty operands (-1) simplify away.
    int combine(FlatCsgNode::Kind kind, int left, int right) {
        using Kind = FlatCsgNode::Kind;
        if (left < 0 && right < 0) return -1;
        if (kind == Kind::unite && (left < 0 || right < 0)) return left < 0 ? right : left;
        if (kind == Kind::intersect && (left < 0 || right < 0)) return -1;
        if (kind == Kind::subtract && (left < 0 || right < 0)) return left;
        object_.nodes.push_back({kind, left, right, -1});
        return static_cast<int>(object_.nodes.size()) - 1;
    }

    /// Union of parts[first, last) as a balanced tree that keeps their order (later parts win);
    /// -1 when empty. Recursion depth is log2 of the count.
    int balanced_union(const std::vector<int>& parts, std::size_t first, std::size_t last) {
        if (first == last) return -1;
        if (last - first == 1) return parts[first];
        const std::size_t middle = first + (last - first) / 2;
        const int left = balanced_union(parts, first, middle);
        const int right = balanced_union(parts, middle, last);
        return combine(FlatCsgNode::Kind::unite, left, right);
    }

    const SceneDesc& scene_;
    bool course_;
    FlatScene out_;
    FlatCsgObject object_;           // the CSG object being expanded (one at a time)
    std::vector<Frame> frames_;      // the path from the root
    std::vector<char> on_path_;      // per scene node: on the current path (cycle check)
    std::size_t expanded_ = 0;       // nodes visited so far
};

}  // namespace

glm::dmat4 compose_transforms(const std::vector<TransformOp>& ops, bool course_convention) {
    glm::dmat4 m(1.0);
    for (const TransformOp& op : ops) m = course_convention ? op_matrix(op) * m : m * op_matrix(op);
    return m;
}

FlatScene flatten_scene(const SceneDesc& scene, int root, bool course_convention) {
    if (root < 0 || root >= static_cast<int>(scene.nodes.size())) throw InputError("render root is not a node");
    return Walker(scene, course_convention).run(root);
}

FlatScene flatten_scene(const RenderJob& job) {
    if (!job.scene) throw InputError("no scene to render");
    FlatScene flat = flatten_scene(*job.scene, job.root, job.options.a4);
    flat.csg_bounding_boxes = !job.options.disable_csg_bb;
    flat.bounding_volumes = !job.options.disable_bv;
    return flat;
}

}  // namespace caustica
