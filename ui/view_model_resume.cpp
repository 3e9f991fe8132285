// The ViewModel's saved accumulations (docs/PREVIEW.md, "Resume"): saving the image of a
// progressive accumulation writes its state beside it, as `caustica render --resume` does, and a
// job whose state lies beside the name Save proposes continues it.
#include "ui/view_model.h"

#include "core/util/printable_text.h"

#include <utility>

namespace caustica::ui {

RenderJob ViewModel::rendered_job(const RenderJob& shown, const JobInputs& inputs) const {
    return job_as_rendered(shown, inputs.scene ? base_options(inputs, true).resolution_override : 0);
}

void ViewModel::request_job(const RenderJob& job) {
    std::optional<AccumulationState> saved;
    if (job.options.accumulates()) {
        // A state of another job is worth a word for the job a scene opens (or reloads) with; not
        // each time the camera or a knob moves away from it.
        const bool scene_opened = looked_for_state_of_.lock() != inputs_.scene;
        looked_for_state_of_ = inputs_.scene;
        continuing_from_ = accumulation_state_path(default_save_path());
        std::optional<ModelNote> note;
        saved = saved_accumulations_.find(continuing_from_, job, rendered_job(job, inputs_), scene_opened, note);
        if (note) note_ = ModelNote{printable_text(note->text), note->problem};
    }
    if (saved) driver_.request_continuing(job, std::move(*saved));
    else driver_.request(job);
}

std::string ViewModel::save_accumulation(const std::string& image_path, bool inside_current_folder) {
    saved_state_key_.reset();
    if (!driver_.job().options.accumulates() || !driver_.accumulation().accumulating) return "";
    const std::string state_path = accumulation_state_path(image_path);
    const std::string shown = printable_text(accumulation_state_path(last_saved_));
    const RenderJob rendered = rendered_job(driver_.job(), running_inputs_.value_or(inputs_));
    AccumulationState state;
    if (driver_.session().accumulation_state(state)) {  // stopped: paused, or ended by a rule
        const int passes = state.next_pass;
        try {
            write_saved_accumulation(state_path, std::move(state), driver_.job(), rendered, inside_current_folder);
            saved_state_key_ = key_without_scene(driver_.job());
        } catch (const std::exception& e) {
            return "\nits accumulation is not saved: " + printable_text(e.what());
        }
        return "\nand its accumulation (" + std::to_string(passes) + " passes) in " + shown +
               ": the copied command line with --resume and -o " + printable_text(image_path) + " continues it";
    }
    if (!driver_.busy()) return "";
    // Refining: the loop copies its state at the end of the pass under way, without stopping.
    driver_.session().request_accumulation_snapshot();
    state_to_write_ = StateToWrite{state_path, shown, inside_current_folder, driver_.job(), rendered, driver_.restarts()};
    return "\nits accumulation goes to " + shown + " at the end of the pass under way";
}

void ViewModel::follow_saved_accumulations() {
    if (std::optional<PreviewDriver::SavedStart> start = driver_.take_saved_start()) {
        const std::string file = printable_text(continuing_from_);
        note_ = start->refusal.empty()
                    ? ModelNote{"continuing " + std::to_string(start->passes) + " passes from " + file, false}
                    : ModelNote{"not continued: " + file + ": " + printable_text(start->refusal), true};
    }
    if (!state_to_write_) return;
    const std::string& shown = state_to_write_->shown;
    AccumulationState state;
    if (driver_.restarts() != state_to_write_->restarts) {  // that accumulation is no longer rendered
        note_ = ModelNote{shown + " not written: another render started before the pass under way ended", true};
        state_to_write_.reset();
        return;
    }
    bool taken = driver_.session().take_accumulation_snapshot(state);
    if (!taken && !driver_.busy()) taken = driver_.session().accumulation_state(state);  // paused before the pass ended
    if (!taken) return;
    const int passes = state.next_pass;
    try {
        write_saved_accumulation(state_to_write_->path, std::move(state), state_to_write_->shown_job, state_to_write_->rendered,
                                 state_to_write_->inside_current_folder);
        note_ = ModelNote{"wrote the accumulation (" + std::to_string(passes) + " passes) in " + shown, false};
        saved_state_key_ = key_without_scene(state_to_write_->shown_job);
    } catch (const std::exception& e) {
        note_ = ModelNote{"the accumulation is not saved: " + printable_text(e.what()), true};
    }
    state_to_write_.reset();
}

}  // namespace caustica::ui
