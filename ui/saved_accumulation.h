// The progressive accumulations the preview saves beside its images and continues when their job
// comes back (docs/PREVIEW.md, "Resume"), in the file `caustica render --resume` keeps
// (docs/OUTPUT.md, "Resuming an accumulation"). GL-free.
#pragma once

#include "core/render/accumulation_state.h"
#include "core/scene/scene_desc.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace caustica::ui {

/// Something the model tells the person once (ViewModel::take_note).
struct ModelNote {
    std::string text;
    bool problem = false;  ///< shown until dismissed
};

/// The preview's job as `caustica render` composes it from the copied command line: an option
/// that sets the image size (--minres, given as `resolution_option`) stays an option there, where
/// the preview folds it into the size. A saved state is keyed by this job, so that `render
/// --resume` with the copied options continues it.
RenderJob job_as_rendered(RenderJob job, int resolution_option);

/// accumulation_key without its costly part, the scene's content (hashed vertex by vertex): 0.
AccumulationKey key_without_scene(const RenderJob& job);

/// Writes `state`, an accumulation of the preview's job `shown`, to `state_path` (atomically, as
/// write_accumulation_state), keyed by `rendered` (job_as_rendered). Throws std::runtime_error
/// "cannot write 'PATH': reason", or when `state` was made for another job than `shown` (its
/// camera, size or options).
void write_saved_accumulation(const std::string& state_path, AccumulationState state, const RenderJob& shown,
                              const RenderJob& rendered, bool inside_current_folder);

/// Finds the saved accumulation that continues a job, reading a file once until it changes.
class SavedAccumulations {
public:
    /// The accumulation saved in `state_path` for `rendered` (job_as_rendered of `shown`), keyed
    /// by `shown` for the session; nullopt when there is no file, or one that does not continue
    /// the job: `note` then says why, for a damaged file (once per file) and, when
    /// `say_mismatch`, for one of another job. The file is never changed.
    std::optional<AccumulationState> find(const std::string& state_path, const RenderJob& shown,
                                          const RenderJob& rendered, bool say_mismatch,
                                          std::optional<ModelNote>& note);

private:
    /// A file as last read, for an image of a size.
    struct Seen {
        std::string path;
        std::filesystem::file_time_type time;
        std::uintmax_t bytes = 0;
        int width = 0, height = 0;
        AccumulationKey key;   ///< what the file was saved for
        std::string problem;   ///< why it cannot be read ("" = none)
        bool problem_said = false;

        bool same_file(const Seen& other) const {
            return path == other.path && time == other.time && bytes == other.bytes && width == other.width &&
                   height == other.height;
        }
    };

    /// Reads the file `seen` names, noting its key or its problem.
    std::optional<AccumulationState> read(Seen& seen);

    std::optional<Seen> seen_;
};

}  // namespace caustica::ui
