// Saving the previewed image: the current samples at the render's resolution, as a PNG written
// atomically, with the scene, camera, options and render state in its text chunks.
#pragma once

#include "core/render/image.h"
#include "core/render/render_session.h"
#include "core/scene/scene_desc.h"

#include <string>
#include <utility>
#include <vector>

namespace caustica::ui {

/// What came of a save.
enum class SaveOutcome {
    written,
    exists,  ///< the file exists and overwriting was not allowed: ask, then save again
    failed,
};

/// A save's outcome and a message for the person.
struct SaveResult {
    SaveOutcome outcome = SaveOutcome::failed;
    std::string message;
};

/// The PNG text chunks of a preview image: software, scene, integrator, camera, options, passes
/// done; for a progressive accumulation also its pass limit, samples per pixel, photons, radius,
/// estimated error and whether it was refining, paused or stopped.
std::vector<std::pair<std::string, std::string>> preview_metadata(const RenderJob& job, const std::string& scene_path,
                                                                  const SessionProgress& progress);

/// Writes `image` to `path` (must end in .png); refuses to replace an existing file unless
/// `overwrite`. The encoding follows the job's --srgb, as the batch command's.
SaveResult save_preview_png(const std::string& path, const Image& image, const RenderJob& job,
                            const std::string& scene_path, const SessionProgress& progress, bool overwrite);

}  // namespace caustica::ui
