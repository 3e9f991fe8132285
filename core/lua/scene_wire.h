// The loader process hands its SceneScript to the renderer's process as bytes: this is that format
// (native byte order: both ends are the same executable). Shared scenes, meshes and images are
// written once and referred to by index. The reader checks every length against what is left, so
// a damaged message is an error, never an oversized allocation or an out-of-bounds read, and it
// bounds the warnings again (core/util/printable_text.h).
#pragma once

#include "core/scene/scene_desc.h"

#include <string>
#include <string_view>

namespace caustica::scene_lua {

/// The script's result as bytes.
std::string encode_scene_script(const SceneScript& script);

/// The SceneScript from encode_scene_script's bytes. Throws std::runtime_error when they are damaged.
SceneScript decode_scene_script(std::string_view bytes);

}  // namespace caustica::scene_lua
