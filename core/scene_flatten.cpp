#include "core/scene_flatten.h"

#include "core/source_location.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

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

    void visit(int index, const glm::dmat4& parent, int inherited_material) {
        const NodeDesc& node = scene.nodes.at(index);
        for (int on_path : path)
            if (on_path == index) throw InputError(node.where, "node '" + node.name + "' contains itself");
        const glm::dmat4 world = parent * compose_transforms(node.transforms, course);
        if (!usable_transform(world))
            throw InputError(node.where, "node '" + node.name + "': its world transform is singular or not finite");
        const int material = node.material >= 0 ? node.material : inherited_material;

        PlacedPrimitive prim;
        prim.object_to_world = world;
        prim.material = material;
        prim.node = index;
        bool is_primitive = true;
        switch (node.kind) {
            case NodeKind::group: is_primitive = false; break;
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
            case NodeKind::csg_union:
            case NodeKind::csg_intersection:
            case NodeKind::csg_difference:
                throw InputError(node.where, "node '" + node.name +
                                                 "': constructive solid geometry is not supported by this build yet");
        }
        if (is_primitive) {
            if (material < 0)
                out.warnings.push_back(node.where.str() + ": node '" + node.name +
                                       "' has no material; it is drawn in grey");
            out.primitives.push_back(prim);
        }
        path.push_back(index);
        for (int child : node.children) visit(child, world, material);
        path.pop_back();
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

}  // namespace caustica
