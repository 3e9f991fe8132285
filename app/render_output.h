// Writing what `caustica render` rendered: the image with its metadata (docs/OUTPUT.md), and what
// -t and -S print about the render.
#pragma once

#include "core/render/image.h"
#include "core/render/render_stats.h"
#include "core/scene/scene_desc.h"

#include <string>

namespace caustica {

/// What -t and -S print for a render (text, so that a rank can send it to rank 0).
std::string stats_text(const RenderStats& stats, bool timing, bool statistics);

/// Writes a rendered frame and reports it (-t/-S: `stats`, or the text another rank made of
/// its own). Returns an exit code (write errors throw).
int write_frame(const RenderJob& job, const std::string& scene_path, const std::string& path, const std::string& frame,
                const Image& image, const RenderStats& stats, const std::string* stats_from_rank = nullptr);

}  // namespace caustica
