// The accumulation the preview keeps aside (PreviewDriver::kept_passes): a change that restarts a
// long progressive accumulation keeps it, and the job coming back continues it from its passes
// (docs/PREVIEW.md, "Progressive refinement"). At most one is kept: it holds the accumulator's
// sums, a few hundred bytes a pixel. A job may also continue an accumulation saved in a file
// (docs/PREVIEW.md, "Resume"), when none kept continues it.
#include "ui/preview_driver.h"

#include "core/scene/options.h"
#include "core/scene/source_location.h"

#include <utility>

namespace caustica::ui {
namespace {

/// Whether `a` and `b` accumulate the same image: the same scene, render call, camera, size and
/// options that feed the image, whatever their stopping rules and threads. One scene description
/// makes one geometry for the same options: nothing is hashed but the options.
bool same_accumulation(const RenderJob& a, const RenderJob& b) {
    if (a.scene != b.scene || a.root != b.root || a.lights != b.lights || a.ambient != b.ambient ||
        a.miss_colour != b.miss_colour || a.width != b.width || a.height != b.height || a.camera.eye != b.camera.eye ||
        a.camera.view != b.camera.view || a.camera.up != b.camera.up || a.camera.fovy_degrees != b.camera.fovy_degrees)
        return false;
    auto options_key = [](Options options) {
        StopRules{}.apply(options);
        return hash_options_feeding(0, options, stage_scene | stage_photons | stage_image);
    };
    return options_key(a.options) == options_key(b.options);
}

}  // namespace

bool PreviewDriver::worth_keeping(const SessionProgress& accumulation) const {
    return accumulation.accumulating && accumulation.passes_done >= 1 &&
           (accumulation.passes_done >= settings_.keep_after_passes ||
            accumulation.accumulated_seconds >= settings_.keep_after_seconds);
}

void PreviewDriver::keep_accumulation() {
    if (kept_ && kept_->job.scene != job_.scene) kept_.reset();  // a reload: it cannot come back
    const SessionProgress& current = accumulation_;
    if (!worth_keeping(current) || (kept_ && kept_progress_.passes_done > current.passes_done)) return;
    std::unique_ptr<KeptAccumulation> taken = session_.take_accumulation();
    if (!taken) return;
    kept_ = std::move(taken);
    kept_progress_ = current;
    kept_overtakable_ = true;
}

std::optional<SessionProgress> PreviewDriver::restore_kept_accumulation() {
    if (!kept_ || !same_accumulation(kept_->job, job_)) return std::nullopt;
    // The accumulation it replaces is kept in its turn (redo brings it back), when worth keeping.
    const SessionProgress replaced = accumulation_;
    std::unique_ptr<KeptAccumulation> back = std::move(kept_);
    const SessionProgress restored = kept_progress_;
    if (worth_keeping(replaced)) kept_ = session_.take_accumulation();
    kept_progress_ = replaced;
    kept_overtakable_ = false;  // the accumulation running now is the one kept before, not a fresh one
    if (!session_.restore_accumulation(std::move(back), job_) || !session_.resume()) {
        session_.start();  // nothing to continue after all: the job from the start
        return std::nullopt;
    }
    return restored;
}

void PreviewDriver::drop_overtaken_accumulation() {
    if (kept_ && kept_overtakable_ && accumulation_.accumulating && accumulation_.passes_done > kept_progress_.passes_done)
        kept_.reset();
}

void PreviewDriver::request_continuing(const RenderJob& job, AccumulationState saved) {
    request(job);
    pending_saved_ = std::move(saved);
}

std::optional<PreviewDriver::SavedStart> PreviewDriver::take_saved_start() { return std::exchange(saved_start_, std::nullopt); }

bool PreviewDriver::start_saved_accumulation(AccumulationState saved) {
    const int passes = saved.next_pass;
    try {
        session_.start_from(std::move(saved));
    } catch (const InputError& e) {  // another job's after all: the job starts from nothing
        saved_start_ = SavedStart{passes, e.what()};
        return false;
    }
    saved_start_ = SavedStart{passes, ""};
    return true;
}

}  // namespace caustica::ui
