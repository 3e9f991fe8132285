// Fuzz target: OBJ text -> MeshData or InputError (gr.mesh's reader, parse_obj_mesh of
// core/geometry/mesh_obj.h, in memory).
#include "fuzz/fuzz_targets.h"

#include "core/geometry/mesh_obj.h"
#include "core/scene/source_location.h"

#include <cmath>
#include <string_view>

namespace caustica::fuzz::obj_reader {

int fuzz_one(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::shared_ptr<const MeshData> mesh;
    try {
        mesh = parse_obj_mesh(text, "fuzz.obj");
    } catch (const InputError&) {
        return 0;
    }
    fuzz_require(mesh != nullptr, "a mesh or an InputError");
    fuzz_require(!mesh->triangles.empty(), "a mesh has triangles");
    for (const glm::vec3& p : mesh->positions)
        fuzz_require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "positions are finite");
    for (const glm::uvec3& t : mesh->triangles)
        fuzz_require(t.x < mesh->positions.size() && t.y < mesh->positions.size() && t.z < mesh->positions.size(),
                     "every triangle index names a position");
    fuzz_require(mesh->texcoords.empty() || mesh->texcoords.size() == 3 * mesh->triangles.size(),
                 "texture coordinates: none or three per triangle");
    for (const glm::vec2& uv : mesh->texcoords)
        fuzz_require(std::isfinite(uv.x) && std::isfinite(uv.y), "texture coordinates are finite");
    return 0;
}

}  // namespace caustica::fuzz::obj_reader
