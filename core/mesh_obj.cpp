// Wavefront OBJ loading with tinyobjloader: positions, fanned triangles, per-corner texcoords.
#include "core/mesh_obj.h"

#include <tiny_obj_loader.h>

#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace caustica {
namespace {

std::string trimmed(std::string text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    return text;
}

/// tinyobjloader reads "nan", "inf" and garbage as 0 without a word: check every number on the
/// `v` and `vt` lines first, so that a bad coordinate is reported with its line.
void check_coordinates(const std::string& text) {
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        std::istringstream tokens(line);
        std::string keyword;
        tokens >> keyword;
        if (keyword != "v" && keyword != "vt") continue;
        for (std::string token; tokens >> token;) {
            if (token[0] == '#') break;
            char* end = nullptr;
            const double value = std::strtod(token.c_str(), &end);
            const std::string where = "line " + std::to_string(number) + ": ";
            if (end != token.c_str() + token.size()) throw InputError(where + "'" + token + "' is not a number");
            if (!std::isfinite(value)) throw InputError(where + "coordinate '" + token + "' is not a finite number");
            if (std::fabs(value) > FLT_MAX) throw InputError(where + "coordinate '" + token + "' is out of range");
        }
    }
}

}  // namespace

std::shared_ptr<const MeshData> load_obj_mesh(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
    const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    if (file.bad()) throw InputError("cannot read '" + path + "'");
    check_coordinates(text);

    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // fanned below, as SCENE_API.md says
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(text, "", config)) throw InputError(trimmed(reader.Error()));
    const tinyobj::attrib_t& attrib = reader.GetAttrib();

    auto mesh = std::make_shared<MeshData>();
    mesh->path = path;
    const size_t vertex_count = attrib.vertices.size() / 3;
    const size_t texcoord_count = attrib.texcoords.size() / 2;
    mesh->positions.reserve(vertex_count);
    for (size_t v = 0; v < vertex_count; ++v)
        mesh->positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);

    bool has_texcoords = false;
    for (const tinyobj::shape_t& shape : reader.GetShapes())
        for (const tinyobj::index_t& corner : shape.mesh.indices) has_texcoords |= corner.texcoord_index >= 0;

    size_t face_number = 0;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (const unsigned char corner_count : shape.mesh.num_face_vertices) {
            ++face_number;
            const tinyobj::index_t* corners = shape.mesh.indices.data() + offset;
            offset += corner_count;
            for (unsigned c = 0; c < corner_count; ++c) {
                const tinyobj::index_t& corner = corners[c];
                if (corner.vertex_index < 0 || static_cast<size_t>(corner.vertex_index) >= vertex_count)
                    throw InputError("face " + std::to_string(face_number) + " refers to vertex " +
                                     std::to_string(corner.vertex_index + 1) + ", but the file has " +
                                     std::to_string(vertex_count) + " vertices");
                if (corner.texcoord_index >= 0 && static_cast<size_t>(corner.texcoord_index) >= texcoord_count)
                    throw InputError("face " + std::to_string(face_number) + " refers to texture coordinate " +
                                     std::to_string(corner.texcoord_index + 1) + ", but the file has " +
                                     std::to_string(texcoord_count));
            }
            for (unsigned k = 1; k + 1 < corner_count; ++k) {  // fan around the first corner
                const tinyobj::index_t* triangle[3] = {&corners[0], &corners[k], &corners[k + 1]};
                mesh->triangles.emplace_back(triangle[0]->vertex_index, triangle[1]->vertex_index,
                                             triangle[2]->vertex_index);
                if (!has_texcoords) continue;
                for (const tinyobj::index_t* corner : triangle) {
                    const int t = corner->texcoord_index;
                    mesh->texcoords.push_back(t < 0 ? glm::vec2(0.0f)
                                                    : glm::vec2(attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]));
                }
            }
        }
    }
    if (mesh->triangles.empty()) throw InputError("no triangles (the file has no faces with 3 or more vertices)");
    return mesh;
}

}  // namespace caustica
