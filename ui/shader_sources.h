// The GLSL sources of shaders/, embedded into the executables at build time.
#pragma once

#include <string_view>

namespace caustica::ui {

/// The text of shaders/<name> (e.g. "image.frag"); throws std::out_of_range for an unknown name.
std::string_view shader_source(std::string_view name);

}  // namespace caustica::ui
