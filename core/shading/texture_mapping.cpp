#include "core/shading/texture_mapping.h"

#include "core/geometry/shapes.h"

#include <cmath>

namespace caustica {
namespace {

constexpr float pi = 3.14159265358979323846f;

// Box face codes (SurfaceCrossing::face).
constexpr int face_minus_x = 0, face_plus_x = 1, face_minus_y = 2, face_plus_y = 3, face_minus_z = 4,
              face_plus_z = 5;
// Cylinder and cone face codes.
constexpr int face_side = 0, face_top_cap = 1;

/// Where one box face sits in the 3x4 unwrap, and how its own (u, v) (shape_uv: u and 1 - v of the
/// face's two axes) turn into the cell's (u, v) so that every cell reads unmirrored from outside.
struct UnwrapCell {
    int column, row;
    bool flip_u, flip_v;
};

/// The cross layout (docs/TEXTURES.md): the middle column folds around the x axis
/// (top, front, bottom, back); -x and +x hang off the front's left and right edges.
UnwrapCell unwrap_cell(int face) {
    switch (face) {
        case face_minus_x: return {0, 1, false, false};
        case face_plus_x: return {2, 1, true, false};
        case face_minus_y: return {1, 2, false, false};
        case face_plus_y: return {1, 0, false, true};
        case face_minus_z: return {1, 3, false, true};
        default: return {1, 1, false, false};  // face_plus_z
    }
}

/// The lookup of the whole image (cell = whole image) or of one unwrap cell on a box face.
TextureLookup box_lookup(const SurfaceHit& hit, bool whole_image) {
    const UnwrapCell cell = unwrap_cell(hit.face);
    const glm::vec2 local(cell.flip_u ? 1.0f - hit.uv.x : hit.uv.x, cell.flip_v ? 1.0f - hit.uv.y : hit.uv.y);
    const glm::vec2 flips(cell.flip_u ? -1.0f : 1.0f, cell.flip_v ? -1.0f : 1.0f);
    TextureLookup lookup;
    lookup.covered = true;
    if (whole_image) {
        lookup.uv = local;
        lookup.jacobian = glm::mat2(flips.x, 0.0f, 0.0f, flips.y);
        return lookup;
    }
    const glm::vec2 cell_size(1.0f / 3.0f, 1.0f / 4.0f);
    const glm::vec2 corner(static_cast<float>(cell.column) * cell_size.x, static_cast<float>(cell.row) * cell_size.y);
    lookup.uv = corner + local * cell_size;
    lookup.jacobian = glm::mat2(flips.x * cell_size.x, 0.0f, 0.0f, flips.y * cell_size.y);
    lookup.window = {corner, corner + cell_size};
    return lookup;
}

/// The planar projection from above onto a cone's side: (x, z) in [-1,1]^2 -> [0,1]^2, apex at
/// the centre. Its Jacobian follows from the side's tangents dp/du = 2 pi (z, 0, -x) and
/// dp/dv = (x / r, -2, z / r) (shape_tangents).
TextureLookup cone_top_lookup(const SurfaceHit& hit) {
    const glm::vec3 p = hit.object_position;
    TextureLookup lookup;
    lookup.covered = true;
    lookup.uv = {0.5f * (p.x + 1.0f), 0.5f * (p.z + 1.0f)};
    const float r = std::sqrt(p.x * p.x + p.z * p.z);
    if (r > 0.0f) lookup.jacobian = glm::mat2(pi * p.z, -pi * p.x, 0.5f * p.x / r, 0.5f * p.z / r);
    else lookup.jacobian = glm::mat2(0.0f);  // the apex: no bump there
    return lookup;
}

/// Mesh texcoords follow the OBJ convention: v = 0 is the image's bottom row.
TextureLookup mesh_lookup(const SurfaceHit& hit) {
    TextureLookup lookup;
    lookup.covered = true;
    lookup.uv = {hit.uv.x, 1.0f - hit.uv.y};
    lookup.jacobian = glm::mat2(1.0f, 0.0f, 0.0f, -1.0f);
    return lookup;
}

TextureLookup default_lookup(const SurfaceHit& hit) {
    TextureLookup lookup;
    lookup.covered = true;
    lookup.uv = hit.uv;
    return lookup;
}

}  // namespace

std::optional<TextureRemap> parse_texture_remap(const std::string& name) {
    if (name.empty()) return TextureRemap::none;
    if (name == "cubetop") return TextureRemap::cube_top;
    if (name == "cubefront") return TextureRemap::cube_front;
    if (name == "cubebot") return TextureRemap::cube_bottom;
    if (name == "cyltop") return TextureRemap::cylinder_top;
    if (name == "conetop") return TextureRemap::cone_top;
    return std::nullopt;
}

TextureLookup texture_lookup(const SurfaceHit& hit, TextureRemap remap) {
    if (hit.shape_kind < 0) return mesh_lookup(hit);
    if (hit.shape_kind == static_cast<int>(ShapeKind::box)) {
        int only_face = -1;
        if (remap == TextureRemap::cube_top) only_face = face_plus_y;
        if (remap == TextureRemap::cube_front) only_face = face_plus_z;
        if (remap == TextureRemap::cube_bottom) only_face = face_minus_y;
        if (only_face < 0) return box_lookup(hit, false);
        if (hit.face != only_face) return {};
        return box_lookup(hit, true);
    }
    if (hit.shape_kind == static_cast<int>(ShapeKind::cylinder) && remap == TextureRemap::cylinder_top) {
        if (hit.face != face_top_cap) return {};
        return default_lookup(hit);  // the cap's own (u, v) is the projection from above
    }
    if (hit.shape_kind == static_cast<int>(ShapeKind::cone) && remap == TextureRemap::cone_top) {
        if (hit.face != face_side) return {};
        return cone_top_lookup(hit);
    }
    return default_lookup(hit);
}

}  // namespace caustica
