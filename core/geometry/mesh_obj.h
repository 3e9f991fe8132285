// Wavefront OBJ loading for gr.mesh.
#pragma once

#include "core/scene/scene_desc.h"

#include <memory>
#include <string>
#include <string_view>

namespace caustica {

/// Reads an OBJ file held in memory: positions (v), texture coordinates (vt) and faces (f with v,
/// v/vt, v//vn or v/vt/vn corners, 1-based or negative = relative indices); every polygon is
/// fanned around its first corner, whatever its size. Per-corner texture coordinates are filled
/// when any face has them (zeros for corners without). Other statements are ignored. Throws
/// InputError "display_name:LINE: message" for a bad number, a non-finite or out-of-float-range
/// coordinate, or an index out of range (however large), and "display_name: no triangles ..."
/// when no face has three corners. `MeshData::path` is set to `source_path` (the file the preview
/// watches for changes), or to `display_name` when that is empty.
std::shared_ptr<const MeshData> parse_obj_mesh(std::string_view text, const std::string& display_name,
                                               const std::string& source_path = {});

/// Reads the file at `path` and parses it with parse_obj_mesh (errors name `path`). Throws
/// InputError when the file cannot be read.
std::shared_ptr<const MeshData> load_obj_mesh(const std::string& path);

}  // namespace caustica
