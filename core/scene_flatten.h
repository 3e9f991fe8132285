// Resolves a render job's node DAG into world-space primitives: composes the transform calls in
// the job's convention (seed: post-multiply; --a4: pre-multiply), resolves gr.cube's extent and
// inherited materials, and checks every world transform.
#pragma once

#include "core/scene_desc.h"
#include "core/shapes.h"

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

/// The world-space content of one render job.
struct FlatScene {
    std::vector<PlacedPrimitive> primitives;
    std::vector<std::string> warnings;
};

/// The local matrix of a node's transform calls in the given convention.
glm::dmat4 compose_transforms(const std::vector<TransformOp>& ops, bool course_convention);

/// Walks the DAG from `root`. Throws InputError naming the node's script line for a singular or
/// non-finite world transform, or for CSG (not supported yet).
FlatScene flatten_scene(const SceneDesc& scene, int root, bool course_convention);

}  // namespace caustica
