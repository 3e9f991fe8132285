// The integrator the person picked for a scene, kept between openings of it (docs/PREVIEW.md,
// "What you see is what you save"): recalled as a pick of the person's when the scene is opened,
// remembered whenever the pick changes (a switch, a reset, an undo).
#include "ui/view_model.h"

#include "ui/view_model_internal.h"

namespace caustica::ui {
namespace {

/// Whether command-line style tokens set --integrator (then the scene's command line decides it,
/// as it decides every option it sets).
bool sets_integrator(const std::vector<std::string>& tokens) {
    Options probe;
    std::vector<std::string> names;
    try {
        apply_option_tokens(probe, tokens, nullptr, &names);
    } catch (const std::exception&) {
        return false;  // compose() reports bad tokens
    }
    return has_token(names, "integrator");
}

}  // namespace

void ViewModel::recall_integrator() {
    remembered_scene_ = scene_path_;
    remembered_integrator_.reset();
    const std::optional<IntegratorKind> kept = integrators_.of(absolute_path(scene_path_));
    if (!kept || sets_integrator(inputs_.tokens)) return;
    try {
        const CausticKnobs current = knobs();
        CausticKnobs picked = current;
        picked.integrator = *kept;
        inputs_.overrides.record(current, picked);  // not an undo step: the scene opens with it
        inputs_.person_knobs = picked;
        if (knob_differs(picked, script_knobs(inputs_), KnobField::integrator)) remembered_integrator_ = kept;
    } catch (const std::exception&) {
        // bad options: compose() reports them, and the scene opens as the script says
    }
}

void ViewModel::remember_integrator() {
    if (!scene_) return;
    std::optional<IntegratorKind> pick;  // none: the scene's own integrator is shown
    try {
        const CausticKnobs shown = knobs();
        if (knob_differs(shown, script_knobs(inputs_), KnobField::integrator)) pick = shown.integrator;
    } catch (const std::exception&) {
        return;  // bad options: compose() reports them
    }
    if (scene_path_ != remembered_scene_) {  // back on a scene after a failed render: what it shows stands
        remembered_scene_ = scene_path_;
        remembered_integrator_ = pick;
        return;
    }
    if (pick == remembered_integrator_) return;
    remembered_integrator_ = pick;
    integrators_.set(absolute_path(scene_path_), pick);
}

bool ViewModel::integrator_kept() const {
    return scene_ && scene_path_ == remembered_scene_ && remembered_integrator_.has_value();
}

}  // namespace caustica::ui
