// Writing what `caustica render` rendered: the image with its metadata (docs/OUTPUT.md), and what
// -t and -S print about the render.
#pragma once

#include "app/animation.h"
#include "core/render/image.h"
#include "core/render/render_layers.h"
#include "core/render/render_stats.h"
#include "core/scene/scene_desc.h"

#include <string>

namespace caustica {

/// What -t and -S print for a render (text, so that a rank can send it to rank 0).
std::string stats_text(const RenderStats& stats, bool timing, bool statistics);

/// Writes a rendered frame to frame.path, its metadata labelled `label` ("3/300" or ""), and
/// reports it (-t/-S: `stats`, or the text another rank made of its own). A script's name is
/// written only inside the current folder, checked when writing (docs/RELIABILITY.md, section 1).
/// Returns an exit code (write errors throw; a script's name that leads outside is InputError).
/// With --layers the file is a multilayer OpenEXR holding `layers` too (docs/OUTPUT.md, "Layers").
int write_frame(const AnimationFrame& frame, const std::string& scene_path, const std::string& label, const Image& image,
                const RenderStats& stats, const std::string* stats_from_rank = nullptr,
                const std::vector<LayerImage>* layers = nullptr);

}  // namespace caustica
