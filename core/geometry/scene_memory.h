// What a flattened scene will cost the renderer once built, counted before anything is built: the
// meshes with Embree's copy of them and their BVH, the placed primitives, the CSG objects and the
// decoded textures. Each part carries the script call that made it, so that a render refused for
// its memory names the line to change (docs/RELIABILITY.md, "Bounded memory").
#pragma once

#include "core/scene/scene_desc.h"
#include "core/scene/scene_flatten.h"

#include <cstddef>
#include <string>
#include <vector>

namespace caustica {

/// Bytes a mesh triangle costs once built (RenderScene::mesh_slot, one Embree scene per mesh
/// whatever its instances, RTC_BUILD_QUALITY_HIGH, a BVH8 of Triangle4 leaves on AVX machines):
///  - our index triple (MeshData::triangles) and Embree's copy of it (rtcSetNewGeometryBuffer): 12 + 12;
///  - Embree's build array, one 32-byte PrimRef (a box with the ids in its spare lanes) a triangle;
///  - the leaves: a Triangle4 holds 4 triangles in 176 bytes (v0, e1, e2 as 4-wide float triples,
///    geometry and primitive ids), 44 bytes a triangle, and Embree reserves 1.2 times the full
///    blocks (its own estimate, bvh_builder_sah.cpp): 52.8;
///  - the nodes: a BVH8 node is 256 bytes (8 child references, 8 boxes as six 8-wide floats) for
///    about 8 x 4 triangles (Embree's estimate again): 8.
/// The robust leaves of a mesh that CSG traces (Triangle4v: v0, v1, v2 and the ids) are the same size.
inline constexpr double mesh_triangle_bytes = 12.0 + 12.0 + 32.0 + 1.2 * 176.0 / 4.0 + 256.0 / (4.0 * 8.0);

/// Bytes a mesh vertex costs once built: our position (MeshData::positions) and Embree's copy.
inline constexpr double mesh_vertex_bytes = 12.0 + 12.0;

/// Bytes the texture coordinates of a triangle cost when the mesh has them: three glm::vec2.
inline constexpr double mesh_texcoord_bytes_per_triangle = 3.0 * 8.0;

/// Bytes a texel of an image texture costs: the decoded 8-bit channels the script sent (counted
/// apart) and the renderer's linear RGB and intensity floats (TextureImage): 12 + 4.
inline constexpr double texture_texel_bytes = 16.0;

/// Bytes every primitive of the top-level scene costs in Embree's build and BVH: a PrimRef (32),
/// its share of a leaf (8) and of a node (8).
inline constexpr double top_level_primitive_bytes = 32.0 + 8.0 + 8.0;

/// Bytes Embree keeps for an instance geometry (rtcNewGeometry(RTC_GEOMETRY_TYPE_INSTANCE)): the
/// object with its Geometry base (callbacks, masks, ids), its two 64-byte transforms and its slot
/// in the scene, rounded up.
inline constexpr double embree_instance_bytes = 512.0;

/// One part of a scene's cost, with the call that made it.
struct MemoryCharge {
    double bytes = 0.0;
    SourceLocation where;  ///< the call's line (empty for jobs made without a script)
    std::string call;      ///< "gr.mesh", "gr.texture", "gr.sphere", "gr.option", "gr.render"
    std::string what;      ///< "the mesh 'tri.obj' (20000000 triangles, 3 vertices)"
};

/// The parts of what `flat` (a flattening of `desc`) costs once RenderScene and the textures are
/// built: each mesh placed anywhere once (mesh_triangle_bytes, mesh_vertex_bytes, texture
/// coordinates), the placed primitives and CSG leaves grouped by the node that made them, each
/// image a material uses once (its decoded pixels and texture_texel_bytes a texel).
std::vector<MemoryCharge> scene_memory_charges(const SceneDesc& desc, const FlatScene& flat);

/// The sum of the charges' bytes.
double total_bytes(const std::vector<MemoryCharge>& charges);

}  // namespace caustica
