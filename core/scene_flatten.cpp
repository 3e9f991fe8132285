#include "core/scene_flatten.h"

#include "core/source_location.h"

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

struct Walker {
    const SceneDesc& scene;
    bool course;
    FlatScene out;
    std::vector<int> path;  // for cycle detection

    /// Enters a node: checks for cycles and the world transform, resolves the material.
    const NodeDesc& enter(int index, const glm::dmat4& parent, int inherited_material, glm::dmat4& world,
                          int& material) {
        const NodeDesc& node = scene.nodes.at(index);
        for (int on_path : path)
            if (on_path == index) throw InputError(node.where, "node '" + node.name + "' contains itself");
        world = parent * compose_transforms(node.transforms, course);
        if (!usable_transform(world))
            throw InputError(node.where, "node '" + node.name + "': its world transform is singular or not finite");
        material = node.material >= 0 ? node.material : inherited_material;
        path.push_back(index);
        return node;
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
                prim.shape = course ? Shape{ShapeKind::box, glm::vec3(0.0f), glm::vec3(1.0f)}
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
            out.warnings.push_back(node.where.str() + ": node '" + node.name + "' has no material; it is drawn in grey");
        return true;
    }

    static bool is_csg(NodeKind kind) {
        return kind == NodeKind::csg_union || kind == NodeKind::csg_intersection || kind == NodeKind::csg_difference;
    }

    void visit(int index, const glm::dmat4& parent, int inherited_material) {
        if (is_csg(scene.nodes.at(index).kind)) {
            // The whole subtree is one CSG object; its children join it as an implicit union.
            FlatCsgObject object;
            object.node = index;
            object.root = csg_subtree(index, parent, inherited_material, object);
            if (object.root >= 0) out.csg_objects.push_back(std::move(object));
            return;
        }
        glm::dmat4 world;
        int material;
        const NodeDesc& node = enter(index, parent, inherited_material, world, material);
        PlacedPrimitive prim;
        if (own_primitive(index, node, world, material, prim)) out.primitives.push_back(prim);
        for (int child : node.children) visit(child, world, material);
        path.pop_back();
    }

    /// Adds a CSG tree node; returns its index. Empty operands (-1) simplify away.
    static int combine(FlatCsgObject& object, FlatCsgNode::Kind kind, int left, int right) {
        using Kind = FlatCsgNode::Kind;
        if (left < 0 && right < 0) return -1;
        if (kind == Kind::unite && (left < 0 || right < 0)) return left < 0 ? right : left;
        if (kind == Kind::intersect && (left < 0 || right < 0)) return -1;
        if (kind == Kind::subtract && (left < 0 || right < 0)) return left;
        object.nodes.push_back({kind, left, right, -1});
        return static_cast<int>(object.nodes.size()) - 1;
    }

    /// Union of parts[first, last) as a balanced tree that keeps their order (later parts win).
    static int balanced_union(FlatCsgObject& object, const std::vector<int>& parts, std::size_t first,
                              std::size_t last) {
        if (first == last) return -1;
        if (last - first == 1) return parts[first];
        const std::size_t middle = first + (last - first) / 2;
        const int left = balanced_union(object, parts, first, middle);
        const int right = balanced_union(object, parts, middle, last);
        return combine(object, FlatCsgNode::Kind::unite, left, right);
    }

    /// Expands the subtree under `index` into `object`; returns its tree node, or -1 when empty.
    int csg_subtree(int index, const glm::dmat4& parent, int inherited_material, FlatCsgObject& object) {
        glm::dmat4 world;
        int material;
        const NodeDesc& node = enter(index, parent, inherited_material, world, material);
        std::vector<int> parts;
        if (is_csg(node.kind)) {
            if (node.csg_left < 0 || node.csg_right < 0)
                throw InputError(node.where, "CSG node '" + node.name + "' needs two operands");
            const int left = csg_subtree(node.csg_left, world, material, object);
            const int right = csg_subtree(node.csg_right, world, material, object);
            const FlatCsgNode::Kind kind = node.kind == NodeKind::csg_union          ? FlatCsgNode::Kind::unite
                                           : node.kind == NodeKind::csg_intersection ? FlatCsgNode::Kind::intersect
                                                                                     : FlatCsgNode::Kind::subtract;
            parts.push_back(combine(object, kind, left, right));
        } else {
            PlacedPrimitive prim;
            if (own_primitive(index, node, world, material, prim)) {
                object.leaves.push_back(prim);
                object.nodes.push_back({FlatCsgNode::Kind::leaf, -1, -1, static_cast<int>(object.leaves.size()) - 1});
                parts.push_back(static_cast<int>(object.nodes.size()) - 1);
            }
        }
        for (int child : node.children) parts.push_back(csg_subtree(child, world, material, object));
        std::erase(parts, -1);
        path.pop_back();
        return balanced_union(object, parts, 0, parts.size());
    }
};

}  // namespace

glm::dmat4 compose_transforms(const std::vector<TransformOp>& ops, bool course_convention) {
    glm::dmat4 m(1.0);
    for (const TransformOp& op : ops) m = course_convention ? op_matrix(op) * m : m * op_matrix(op);
    return m;
}

FlatScene flatten_scene(const SceneDesc& scene, int root, bool course_convention) {
    if (root < 0 || root >= static_cast<int>(scene.nodes.size())) throw InputError("render root is not a node");
    Walker walker{scene, course_convention, {}, {}};
    walker.visit(root, glm::dmat4(1.0), -1);
    return std::move(walker.out);
}

FlatScene flatten_scene(const RenderJob& job) {
    if (!job.scene) throw InputError("no scene to render");
    FlatScene flat = flatten_scene(*job.scene, job.root, job.options.a4);
    flat.csg_bounding_boxes = !job.options.disable_csg_bb;
    flat.bounding_volumes = !job.options.disable_bv;
    return flat;
}

}  // namespace caustica
