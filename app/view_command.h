// `caustica view`: hands over to the preview executables, so that this one links no GL.
#pragma once

#include <string>
#include <vector>

namespace caustica {

/// Runs `caustica view ARGS...` by exec'ing caustica-view (a window) or, without a DISPLAY or
/// with --headless, caustica-view-headless (OSMesa), both from this executable's folder.
/// Returns only when that fails, with the exit code.
int run_view_command(const std::vector<std::string>& args);

}  // namespace caustica
