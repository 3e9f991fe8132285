#include "ui/saved_accumulation.h"

#include "core/render/fingerprints.h"

#include <memory>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace caustica::ui {
namespace {

namespace fs = std::filesystem;

/// Why a file found beside the image is left alone: `problem` is "PATH: reason".
std::string not_continued(const std::string& problem) {
    return "not continued: " + problem + " (the preview starts afresh; the file is kept until you save there)";
}

}  // namespace

RenderJob job_as_rendered(RenderJob job, int resolution_option) {
    if (resolution_option > 0 && job.width == resolution_option && job.height == resolution_option)
        job.options.resolution_override = resolution_option;
    return job;
}

AccumulationKey key_without_scene(const RenderJob& job) {
    // The same job over an empty scene: the camera, options and size are hashed as they are.
    RenderJob probe;
    probe.scene = std::make_shared<const SceneDesc>();
    probe.camera = job.camera;
    probe.options = job.options;
    probe.width = job.width;
    probe.height = job.height;
    AccumulationKey key = accumulation_key(probe);
    key.scene = 0;
    return key;
}

void write_saved_accumulation(const std::string& state_path, AccumulationState state, const RenderJob& shown,
                              const RenderJob& rendered, bool inside_current_folder) {
    AccumulationKey made = state.key;
    made.scene = 0;
    if (const std::string why = accumulation_mismatch(made, key_without_scene(shown)); !why.empty())
        throw std::runtime_error("the accumulation at hand is another job's: " + why);
    state.key = accumulation_key(rendered);
    write_accumulation_state(state_path, state, inside_current_folder);
}

std::optional<AccumulationState> SavedAccumulations::read(Seen& seen) {
    try {
        AccumulationState state = read_accumulation_state(seen.path, seen.width, seen.height);
        seen.key = state.key;
        seen.problem.clear();
        return state;
    } catch (const std::exception& e) {  // InputError "PATH: reason", or no memory for it
        seen.problem = e.what();
        return std::nullopt;
    }
}

std::optional<AccumulationState> SavedAccumulations::find(const std::string& state_path, const RenderJob& shown,
                                                          const RenderJob& rendered, bool say_mismatch,
                                                          std::optional<ModelNote>& note) {
    std::error_code ec;
    if (!fs::exists(state_path, ec)) return std::nullopt;
    Seen now;
    now.path = state_path;
    now.time = fs::last_write_time(state_path, ec);
    now.bytes = ec ? 0 : fs::file_size(state_path, ec);
    const AccumulationKey wanted = key_without_scene(rendered);
    now.width = wanted.width;
    now.height = wanted.height;
    std::optional<AccumulationState> state;
    if (!seen_ || !seen_->same_file(now)) {  // read it once: later jobs compare with its key
        seen_ = now;
        state = read(*seen_);
    }
    if (!seen_->problem.empty()) {
        if (!seen_->problem_said) note = ModelNote{not_continued(seen_->problem), true};
        seen_->problem_said = true;
        return std::nullopt;
    }
    // The cheap parts first (a camera that moved ends it here), the scene's content last.
    AccumulationKey key = wanted;
    key.scene = seen_->key.scene;
    std::string mismatch = accumulation_mismatch(seen_->key, key);
    if (mismatch.empty()) {
        key.scene = scene_content_fingerprint(rendered);
        mismatch = accumulation_mismatch(seen_->key, key);
    }
    if (!mismatch.empty()) {
        if (say_mismatch) note = ModelNote{not_continued(state_path + ": " + mismatch), true};
        return std::nullopt;
    }
    if (!state) state = read(*seen_);  // its sums were not kept while other jobs were shown
    if (!state) {
        note = ModelNote{not_continued(seen_->problem), true};
        seen_->problem_said = true;
        return std::nullopt;
    }
    // The file may have been written again within its timestamp's tick: what was read decides.
    if (const std::string again = accumulation_mismatch(state->key, key); !again.empty()) {
        if (say_mismatch) note = ModelNote{not_continued(state_path + ": " + again), true};
        return std::nullopt;
    }
    // The session checks it against the job it renders, the preview's: the same scene.
    state->key = key_without_scene(shown);
    state->key.scene = key.scene;
    return state;
}

}  // namespace caustica::ui
