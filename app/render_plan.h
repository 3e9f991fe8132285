// What `caustica render` renders, worked out before any rendering: the command line parsed, the
// script run, its frames planned and their outputs checked.
#pragma once

#include "app/animation.h"
#include "core/scene/scene_desc.h"
#include "core/scene/source_location.h"

#include <string>
#include <vector>

namespace caustica {

class RenderSession;

/// The command line of `caustica render`, parsed.
struct RenderArguments {
    std::vector<std::string> option_tokens;  ///< everything but the scene and -o
    std::string scene;
    std::string output;                       ///< -o, or "" for the names the script gives
    std::vector<std::string> allow_read;      ///< --allow-read folders (command line only)
    AnimationRequest animation;               ///< --frames, --orbit-frames (command line only)
    bool resume = false;                      ///< --resume: continue and keep the saved accumulation
    bool help = false;
};

/// What a render command renders, once its arguments, script and frames are checked.
struct RenderPlan {
    RenderArguments parsed;
    AnimationPlan plan;
    bool numbered = false;  ///< frames are numbered in the images' metadata
};

/// Everything before rendering: arguments, the script, the frames, the outputs (checked where
/// they are written: `writes`), the orbit's target. Returns an exit code to end with at once
/// (help, interrupted), or -1 to render.
int plan_render(const std::vector<std::string>& args, RenderSession& session, bool writes, RenderPlan& out);

/// The scene error (exit 2) of a job whose output leads outside the current folder: `reason` is
/// the message of OutputOutsideFolder.
InputError output_outside(const RenderJob& job, const std::string& reason);

/// The scene error (exit 2) of a job that needs more memory than there is to render `path`.
InputError out_of_memory(const RenderJob& job, const std::string& path);

}  // namespace caustica
