// Wavefront OBJ loading for gr.mesh.
#pragma once

#include "core/scene_desc.h"

#include <memory>
#include <string>

namespace caustica {

/// Loads positions, triangles (polygons fanned) and per-corner texture coordinates when present.
/// Throws InputError (without location; the caller adds it) when the file is missing or malformed,
/// has no triangles, or holds a non-finite coordinate or an index out of range.
std::shared_ptr<const MeshData> load_obj_mesh(const std::string& path);

}  // namespace caustica
