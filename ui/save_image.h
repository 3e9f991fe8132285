// Saving the previewed image: the current samples at the render's resolution, as a PNG, OpenEXR or
// PFM file (by extension) written atomically, with the scene, camera, options and render state in
// its metadata (PNG text chunks, EXR string attributes; PFM has none).
#pragma once

#include "core/io/output_folder.h"
#include "core/render/image.h"
#include "core/render/render_session.h"
#include "core/scene/scene_desc.h"
#include "core/io/tonemap.h"

#include <optional>

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

/// The options that render what `progress` shows of `job`, as the metadata names them: an
/// accumulation not ended yet gets `--passes` with the passes done in place of its stopping rules
/// (`caustica render` accepts every such list: check_render_stop_rules).
Options rendered_options(const RenderJob& job, const SessionProgress& progress);

/// The PNG text chunks of a preview image: software, scene, integrator, camera, options, passes
/// done; for a progressive accumulation also its pass limit, samples per pixel, photons, radius,
/// estimated error and whether it was refining, paused or stopped.
std::vector<std::pair<std::string, std::string>> preview_metadata(const RenderJob& job, const std::string& scene_path,
                                                                  const SessionProgress& progress);

/// How a saved PNG maps linear values (EXR and PFM take the exposure only).
struct SaveToneSettings {
    Tonemap tonemap = Tonemap::clamp;
    float exposure_stops = 0.0f;
};

/// Writes `image` to `path` as PNG, OpenEXR or PFM by its extension (.png, .exr, .pfm, any case);
/// refuses to replace an existing file unless `overwrite`. PNG follows the job's --srgb, and
/// `tone` (default: the job's --tonemap and --exposure); EXR is linear, unclamped, half or the
/// job's --exr-pixel float, exposure applied; PFM likewise in float. The metadata names the camera
/// actually rendered (job.camera: the orbited one). The message names the absolute path written.
/// `place` is OutputPlace::inside_current_folder when `path` is the script's gr.render name: it
/// is then written only inside the current folder, as `caustica render` writes it, and refused
/// with the gr.render's file:line otherwise (docs/RELIABILITY.md, section 1).
SaveResult save_preview_image(const std::string& path, const Image& image, const RenderJob& job,
                              const std::string& scene_path, const SessionProgress& progress, bool overwrite,
                              std::optional<SaveToneSettings> tone = std::nullopt,
                              OutputPlace place = OutputPlace::anywhere);

/// save_preview_image for a path that must end in .png (kept for existing callers).
SaveResult save_preview_png(const std::string& path, const Image& image, const RenderJob& job,
                            const std::string& scene_path, const SessionProgress& progress, bool overwrite);

}  // namespace caustica::ui
