#include "core/geometry/scene_memory.h"

#include "core/geometry/csg_tree.h"
#include "core/geometry/render_scene.h"
#include "core/io/png_io.h"
#include "core/scene/scene_validate.h"

#include <set>

namespace caustica {
namespace {

/// A primitive placed in the world: its flattened record (alive during the build), what the
/// renderer keeps of it, and its place in the top-level BVH.
constexpr double analytic_placement_bytes = sizeof(PlacedPrimitive) + sizeof(RenderScene::AnalyticPrimitive) +
                                            2 * sizeof(glm::vec3) /* its box */ + top_level_primitive_bytes;
/// A mesh instance: as above, with its transform waiting for the build and Embree's instance.
constexpr double instance_placement_bytes = sizeof(PlacedPrimitive) + sizeof(RenderScene::MeshInstance) +
                                            sizeof(glm::mat4) + 2 * sizeof(int) /* waiting for the build */ +
                                            embree_instance_bytes + top_level_primitive_bytes;
/// A leaf of a CSG object: its flattened record and the tree's leaf.
constexpr double csg_leaf_bytes = sizeof(PlacedPrimitive) + sizeof(CsgLeaf);
/// A node of a CSG object: its flattened node and the tree's (kind, three indices, a box, a flag).
constexpr double csg_node_bytes = sizeof(FlatCsgNode) + 4 + 3 * 4 + 2 * sizeof(glm::vec3) + 4;

MemoryCharge mesh_charge(const MeshData& mesh, const NodeDesc* made_by) {
    const double triangles = static_cast<double>(mesh.triangles.size());
    MemoryCharge charge;
    charge.bytes = triangles * mesh_triangle_bytes + static_cast<double>(mesh.positions.size()) * mesh_vertex_bytes +
                   (mesh.texcoords.empty() ? 0.0 : triangles * mesh_texcoord_bytes_per_triangle);
    if (made_by) charge.where = made_by->where;
    charge.call = "gr.mesh";
    charge.what = "the mesh" + (mesh.path.empty() ? std::string() : " '" + mesh.path + "'") + " (" +
                  std::to_string(mesh.triangles.size()) + " triangles, " + std::to_string(mesh.positions.size()) +
                  " vertices)";
    return charge;
}

/// Each mesh placed anywhere (standalone or inside CSG) once: RenderScene builds one BVH a mesh.
void charge_meshes(const SceneDesc& desc, const FlatScene& flat, std::vector<MemoryCharge>& out) {
    std::set<int> meshes;
    for (const PlacedPrimitive& p : flat.primitives)
        if (p.is_mesh) meshes.insert(p.mesh);
    for (const FlatCsgObject& object : flat.csg_objects)
        for (const PlacedPrimitive& leaf : object.leaves)
            if (leaf.is_mesh) meshes.insert(leaf.mesh);
    std::vector<const NodeDesc*> made_by(desc.meshes.size(), nullptr);  // the first gr.mesh of each
    for (const NodeDesc& node : desc.nodes)
        if (node.kind == NodeKind::mesh && node.mesh >= 0 && node.mesh < static_cast<int>(made_by.size()) &&
            !made_by[static_cast<std::size_t>(node.mesh)])
            made_by[static_cast<std::size_t>(node.mesh)] = &node;
    for (int mesh : meshes) {
        const std::size_t index = static_cast<std::size_t>(mesh);
        out.push_back(mesh_charge(*desc.meshes.at(index), made_by.at(index)));
    }
}

/// The placed primitives, one charge per node that made them (a node reused a million times is one
/// charge), then each CSG object's leaves and nodes, charged to its CSG call.
void charge_placements(const SceneDesc& desc, const FlatScene& flat, std::vector<MemoryCharge>& out) {
    const std::size_t nodes = desc.nodes.size();
    std::vector<double> bytes_of_node(nodes + 1, 0.0);  // the last slot: primitives of no known node
    std::vector<std::size_t> placements_of_node(nodes + 1, 0);
    for (const PlacedPrimitive& p : flat.primitives) {
        const bool known = p.node >= 0 && static_cast<std::size_t>(p.node) < nodes;
        const std::size_t node = known ? static_cast<std::size_t>(p.node) : nodes;
        bytes_of_node[node] += p.is_mesh ? instance_placement_bytes : analytic_placement_bytes;
        ++placements_of_node[node];
    }
    for (std::size_t node = 0; node <= nodes; ++node) {
        const std::size_t count = placements_of_node[node];
        if (count == 0) continue;
        MemoryCharge charge;
        charge.bytes = bytes_of_node[node];
        charge.what = "the primitive made here, placed " + std::to_string(count) + (count == 1 ? " time" : " times");
        if (node < nodes) {
            charge.where = desc.nodes[node].where;
            charge.call = node_call(desc.nodes[node].kind);
        }
        out.push_back(std::move(charge));
    }
    for (const FlatCsgObject& object : flat.csg_objects) {
        MemoryCharge charge;
        charge.bytes = static_cast<double>(object.leaves.size()) * csg_leaf_bytes +
                       static_cast<double>(object.nodes.size()) * csg_node_bytes + top_level_primitive_bytes;
        charge.what = "the CSG object made here (" + std::to_string(object.leaves.size()) + " primitives)";
        if (object.node >= 0 && static_cast<std::size_t>(object.node) < nodes) {
            charge.where = desc.nodes[static_cast<std::size_t>(object.node)].where;
            charge.call = node_call(desc.nodes[static_cast<std::size_t>(object.node)].kind);
        }
        out.push_back(std::move(charge));
    }
}

/// Each image a material uses, once however many textures and materials share it (the renderer
/// converts each decoded image once).
void charge_textures(const SceneDesc& desc, std::vector<MemoryCharge>& out) {
    std::set<const Png8*> charged;
    auto charge_texture = [&](int index, const char* call) {
        if (index < 0 || index >= static_cast<int>(desc.textures.size())) return;
        const TextureDesc& texture = desc.textures[static_cast<std::size_t>(index)];
        if (!texture.image || !charged.insert(texture.image.get()).second) return;
        const Png8& image = *texture.image;
        const double texels = static_cast<double>(image.width) * static_cast<double>(image.height);
        MemoryCharge charge;
        charge.bytes = static_cast<double>(image.data.size()) + texels * texture_texel_bytes;
        charge.where = texture.where;
        charge.call = call;
        charge.what = "the image '" + texture.source + "' (" + std::to_string(image.width) + " x " +
                      std::to_string(image.height) + ")";
        out.push_back(std::move(charge));
    };
    for (const MaterialDesc& material : desc.materials) {
        charge_texture(material.texture, "gr.texture");
        charge_texture(material.bumpmap, "gr.bumpmap");
    }
}

}  // namespace

std::vector<MemoryCharge> scene_memory_charges(const SceneDesc& desc, const FlatScene& flat) {
    std::vector<MemoryCharge> charges;
    charge_meshes(desc, flat, charges);
    charge_placements(desc, flat, charges);
    charge_textures(desc, charges);
    return charges;
}

double total_bytes(const std::vector<MemoryCharge>& charges) {
    double total = 0.0;
    for (const MemoryCharge& charge : charges) total += charge.bytes;
    return total;
}

}  // namespace caustica
