// Taking a progressive accumulation out of a RenderSession and putting it back: the preview keeps
// the last long accumulation a change restarted, so that undoing the change continues it instead of
// starting again (docs/PREVIEW.md, "Progressive refinement").
#include "core/render/render_session.h"

#include <utility>

namespace caustica {

std::unique_ptr<KeptAccumulation> RenderSession::take_accumulation() {
    cancel();
    if (worker_.joinable()) worker_.join();
    if (!loop_ || !loop_->resumable() || !job_.options.accumulates() || image_.width != job_.width ||
        image_.height != job_.height)
        return nullptr;
    auto kept = std::make_unique<KeptAccumulation>();
    kept->job = job_;
    kept->loop = std::move(loop_);  // the next set_job makes a fresh loop
    kept->kind = loop_kind_;
    kept->image = image_;
    return kept;
}

bool RenderSession::restore_accumulation(std::unique_ptr<KeptAccumulation> kept, const RenderJob& job) {
    set_job(job);  // the worker has stopped, the stages are keyed by this job
    if (!kept || !kept->loop || kept->kind != loop_kind_ || !job_.options.accumulates() ||
        kept->image.width != job_.width || kept->image.height != job_.height)
        return false;
    loop_ = std::move(kept->loop);
    if (image_.width != job_.width || image_.height != job_.height) make_image(job_.width, job_.height);
    // Published whole, as a render publishes its tiles: the viewer copies the kept image next.
    image_ = std::move(kept->image);
    for (std::size_t i = 0; i < tiles_.size(); ++i) tile_versions_[i].store(++version_counter_, std::memory_order_release);
    return true;
}

}  // namespace caustica
