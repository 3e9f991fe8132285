// Resolves a render job's node DAG into world-space primitives: composes the transform calls in the
// job's convention (the original's: post-multiply; --a4: pre-multiply), resolves gr.cube's extent
// and inherited materials, and checks every world transform.
#pragma once

#include "core/scene/scene_desc.h"
#include "core/geometry/shapes.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace caustica {

/// An analytic shape or a mesh instance placed in the world.
struct PlacedPrimitive {
    bool is_mesh = false;
    Shape shape;                 ///< when !is_mesh
    int mesh = -1;               ///< index into SceneDesc::meshes when is_mesh
    glm::dmat4 object_to_world{1.0};
    int material = -1;           ///< index into SceneDesc::materials; -1 = default material
    int node = -1;               ///< the node that made it (for messages)
};

/// One node of a flattened CSG tree: an operation on two other nodes, or a leaf primitive.
struct FlatCsgNode {
    enum class Kind { leaf, unite, intersect, subtract };
    Kind kind = Kind::leaf;
    int left = -1, right = -1;  ///< operand nodes (indices into FlatCsgObject::nodes)
    int leaf = -1;              ///< index into FlatCsgObject::leaves for a leaf
};

/// A CSG object: the tree under a CSG node expanded to world space (a DAG reused inside the tree
/// is copied per use). Groups and a node's children are implicit unions, later children
/// winning where media overlap (docs/SCENE_LANGUAGE.md, "CSG media").
struct FlatCsgObject {
    int node = -1;                          ///< the CSG node that made it (for messages)
    std::vector<PlacedPrimitive> leaves;    ///< world transforms and inherited materials
    std::vector<FlatCsgNode> nodes;
    int root = -1;                          ///< index into nodes
};

/// The world-space content of one render job.
struct FlatScene {
    std::vector<PlacedPrimitive> primitives;  ///< standalone primitives (not CSG operands)
    std::vector<FlatCsgObject> csg_objects;
    bool csg_bounding_boxes = true;           ///< test the boxes of CSG subtrees (off: --disable-csg-bb)
    bool bounding_volumes = true;             ///< off (--disable-bv): analytic primitives tested one by one
    std::vector<std::string> warnings;
};

/// The local matrix of a node's transform calls in the given convention.
glm::dmat4 compose_transforms(const std::vector<TransformOp>& ops, bool course_convention);

/// Walks the DAG from `root` (iteratively: any nesting depth). Throws InputError naming the node's
/// script line for a singular or non-finite world transform, a cycle, a CSG node without two
/// operands, or a scene that reuse expands to more than five million nodes.
FlatScene flatten_scene(const SceneDesc& scene, int root, bool course_convention);

/// Flattens a render job with its options (the convention, --disable-csg-bb, --disable-bv).
FlatScene flatten_scene(const RenderJob& job);

}  // namespace caustica
